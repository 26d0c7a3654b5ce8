// Chapter 13: a scene of instances where a backend reads it, and what runs over it: batches
// of rays through both levels, the shaded image with shadows, and the moving scene's frame
// (instances moved, top level rebuilt). Every pass is one RT_HD function run on the GPU or on
// CPU threads (chapter 10's for_each_index), so both backends trace the same scene.
#pragma once

#include <memory>
#include <vector>

#include "camera_spec.h"
#include "instance_scene.h"
#include "rt/backend.h"
#include "rt/image.h"
#include "rt/launch.h"
#include "two_level.h"

namespace rt::ch13 {

// What the shaded image needs beyond the trace: each mesh's triangles (for the normal at a hit)
// and each instance's colour, and the sun.
struct ShadeView {
  const ch04::MeshView* meshes = nullptr; // by mesh number
  const Vec3f* albedo = nullptr;          // by instance
  Vec3f to_sun{0.424f, 0.848f, 0.318f};   // unit (to 2e-6): (4, 8, 3) / |(4, 8, 3)|
};

class TwoLevelScene {
public:
  // The bottom level's trees, the meshes, the instances and their boxes copied to the backend,
  // and the top level built once. `spins` (one per instance from the first, or none) lets
  // move() turn those instances.
  TwoLevelScene(Backend backend, const InstanceScene& scene, const BottomLevel& bottom,
                std::vector<Spin> spins = {}, TopLayout top = TopLayout::binary);
  ~TwoLevelScene();
  TwoLevelScene(const TwoLevelScene&) = delete;
  TwoLevelScene& operator=(const TwoLevelScene&) = delete;

  Backend backend() const;
  TopLayout top_layout() const;
  int instance_count() const;
  int entry_count() const; // the top level's leaves: instances, opened into subtrees
  TwoLevelView view() const;
  ShadeView shade_view() const;
  // The top level built again over the instances' current boxes (and, for the wide layout,
  // collapsed to chapter 09's 4-wide node by chapter 10's parallel collapse): queued on the
  // GPU.
  void build_top();
  // The spinning instances placed for time `seconds` (transforms and boxes, in double on the
  // backend), then build_top(): one frame of the moving scene, queued on the GPU.
  void move(double seconds);
  // Bytes the backend holds: the bottom level (nodes and triangles) and the top level with the
  // instances.
  double bottom_bytes() const;
  double top_bytes() const;

private:
  struct Arrays;
  std::unique_ptr<Arrays> arrays_;
};

// `count` rays into `hits`, closest or any hit (backend pointers).
void trace_rays(const TwoLevelScene& scene, Query query, const RayF* rays, int count,
                InstanceHit* hits);

// The shaded image into `pixels` (backend pointer, width * height): each pixel's closest hit
// lit by the sun, with its shadow ray, and a sky where nothing is hit.
void render_shaded(const TwoLevelScene& scene, const ch03::Camera<float>& camera, Extent extent,
                   Rgba8* pixels);

} // namespace rt::ch13
