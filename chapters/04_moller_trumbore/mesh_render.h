// Chapter 04: a triangle scene through the camera of chapter 03, brute force (every ray tests
// every triangle), with either intersection test, on either backend, against a float64
// reference. Holes are what leaks look like in an image: pixels where the float render sees
// nothing while the reference sees a surface.
#pragma once

#include <cstdint>
#include <vector>

#include "camera_spec.h"
#include "mesh_gen.h"
#include "rt/backend.h"
#include "rt/device_buffer.h"
#include "rt/image.h"
#include "triangles.h"

namespace rt::ch04 {

using ch03::CameraSpec;

// Closed meshes and a floor quad in one indexed mesh; object[i] says which the triangle
// belongs to (its colour).
struct TriangleScene {
  Mesh mesh;
  std::vector<std::int32_t> object;
};

// An icosphere, a box and a floor quad, all moved by `offset` (the camera must move with it).
TriangleScene make_demo_scene(int sphere_subdivisions, Vec3d offset);

// The scene in device memory, owned; view() is what kernels read.
class DeviceTriangleScene {
public:
  explicit DeviceTriangleScene(const TriangleScene& scene);
  MeshView view() const;
  const std::int32_t* object() const { return object_.data(); }

private:
  DeviceBuffer<Vec3f> vertices_;
  DeviceBuffer<IndexedTriangle> triangles_;
  DeviceBuffer<std::int32_t> object_;
};

struct MeshPixelRecord {
  float t;      // primary hit distance, infinity for none
  int triangle; // -1 for none
  int nan;      // 1 if the colour came out NaN
};

// Fills the image (device memory on the GPU backend, with `mesh` and `object` in device
// memory too; host memory on the CPU backend). records may be null.
void render_triangles(Backend backend, TriangleVariant variant, MeshView mesh,
                      const std::int32_t* object, const ch03::Camera<float>& camera,
                      Extent extent, Rgba8* pixels, MeshPixelRecord* records = nullptr);

// The float64 reference: the watertight test in double on the float camera's rays.
struct MeshReference {
  Image image;
  std::vector<int> triangle; // per pixel, -1 for none
};
MeshReference render_triangles_reference(const TriangleScene& scene, const CameraSpec& camera,
                                         Extent extent);

struct MeshFrameError {
  long long pixels_differing = 0;
  long long holes = 0; // background where the reference sees a surface
  long long nan_pixels = 0;
};
MeshFrameError compare_with_reference(const Image& image,
                                      const std::vector<MeshPixelRecord>& records,
                                      const MeshReference& reference);

} // namespace rt::ch04
