// Chapter 10: the moving scene's frames made where they are traced. The rest pose goes to the
// backend once; each frame a pass moves the vertices, the LBVH is built from them (or last
// frame's tree refitted), collapsed to chapter 09's 4-wide packed tree and the shaded frame
// traced through it, without a trip to the host. moving_scene_at stays the reference.
#pragma once

#include <memory>
#include <vector>

#include "animation.h"
#include "builders.h"
#include "bvh.h"
#include "camera.h"
#include "rt/backend.h"
#include "rt/image.h"
#include "wide_bvh.h"

namespace rt::ch10 {

// One frame's parts: GPU, CUDA events between them; CPU, wall time.
struct FrameParts {
  double animate_ms = 0, tree_ms = 0, collapse_ms = 0, render_ms = 0;
};

class MovingFrames {
public:
  // The torus scene of `detail` (moving_scene_at's) on the resolved backend, its tree built by
  // `builder`: the LBVH's passes on the backend; another builder from the vertices copied to
  // the host, its tree copied back (the refit and the rest stay on the backend).
  // With a `model` (fit_moving_model's), the waving model in the torus's place.
  // `rule`: how the tree is collapsed to 4-wide (wide_collapse.h).
  MovingFrames(Backend backend, Builder builder, int detail, const ch04::Mesh* model = nullptr,
               CollapseRule rule = CollapseRule::sah);
  ~MovingFrames();
  MovingFrames(const MovingFrames&) = delete;
  MovingFrames& operator=(const MovingFrames&) = delete;

  // The scene at `time`: vertices moved, the tree rebuilt (or, for refit after a first
  // build, refitted), collapsed, and chapter 06's shaded frame (flat normals, shadows) traced
  // into `pixels` (backend memory), waited for.
  FrameParts frame(double time, Update update, const ch03::Camera<float>& camera, Extent extent,
                   Rgba8* pixels);

  // The frame's first three parts alone, for a renderer of its own (chapter 11's path
  // tracer): the vertices moved to `time`, the tree updated and collapsed, in the arrays that
  // mesh() and wide_view() point at; render_ms is 0. On the GPU nothing waits but the clock.
  FrameParts move(double time, Update update);
  // Where the moved scene lives (backend pointers): the same arrays every frame, rewritten in
  // place, so that a view made once follows the scene.
  ch04::MeshView mesh() const;
  ch09::Wide4PackedBvh::View wide_view() const;

  // What the last frame made, copied to the host (for reports and tests).
  std::vector<Vec3f> vertices() const;
  ch07::Bvh binary_tree() const; // stats filled
  ch09::Wide4PackedBvh wide_tree() const;
  long long triangles() const;

private:
  struct State;
  std::unique_ptr<State> state_;
};

} // namespace rt::ch10
