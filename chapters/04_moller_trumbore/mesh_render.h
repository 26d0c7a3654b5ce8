// Chapter 04: a triangle scene through the camera of chapter 03, brute force (every ray tests
// every triangle), with either intersection test, on either backend, against a float64
// reference. Holes are what leaks look like in an image: pixels where the float render sees
// nothing while the reference sees a surface.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "camera_spec.h"
#include "mesh_gen.h"
#include "rt/backend.h"
#include "rt/device_buffer.h"
#include "rt/image.h"
#include "triangles.h"

namespace rt::ch04 {

using ch03::CameraSpec;

// The nearest triangle in precision T, brute force (every triangle), with its geometric normal;
// the float64 reference converts each float vertex. Chapters that shade a mesh start here.
template <class T> struct NearestTriangle {
  T t = std::numeric_limits<T>::infinity();
  int index = -1;
  Vec3<T> normal{}; // geometric, not normalised
};

template <class T>
RT_HD NearestTriangle<T> nearest_triangle(TriangleVariant variant, MeshView mesh, Ray<T> ray) {
  NearestTriangle<T> nearest;
  for (int i = 0; i < mesh.triangle_count; ++i) {
    const IndexedTriangle k = mesh.triangles[i];
    const Triangle<T> tri{mesh.vertices[k.v0].as<T>(), mesh.vertices[k.v1].as<T>(),
                          mesh.vertices[k.v2].as<T>()};
    const TriangleHit<T> hit = intersect_triangle(variant, ray, tri);
    if (hit.hit) {
      nearest = {hit.t, i, cross(tri.v1 - tri.v0, tri.v2 - tri.v0)};
      ray.tmax = hit.t;
    }
  }
  return nearest;
}

// n at unit length, for a normal of any size. A triangle's normal, the cross product of its
// edges, squares their size, and the squared length that normalize() forms squares it again:
// beyond float's range for edges above ~1e9 or below ~1e-10 (NaN pixels). Scaling n first by
// the power of two that brings its largest component near 1 is exact, so the result is bit
// for bit normalize(n) wherever that is finite, and finite everywhere else.
RT_HD inline float scaled_by_power_of_two(float x, int exponent) { return ldexpf(x, exponent); }
RT_HD inline double scaled_by_power_of_two(double x, int exponent) {
  return ldexp(x, exponent);
}
RT_HD inline int binary_exponent(float x) { return ilogbf(x); }
RT_HD inline int binary_exponent(double x) { return ilogb(x); }
template <class T> RT_HD Vec3<T> unit_normal(Vec3<T> n) {
  const T largest = max_component(elementwise_abs(n));
  if (!(largest > T(0) && is_finite(largest))) return normalize(n); // no direction: NaN
  const int exponent = binary_exponent(largest);
  return normalize(Vec3<T>{scaled_by_power_of_two(n.x, -exponent),
                           scaled_by_power_of_two(n.y, -exponent),
                           scaled_by_power_of_two(n.z, -exponent)});
}

// Closed meshes and a floor quad in one indexed mesh; object[i] says which the triangle
// belongs to (its colour).
struct TriangleScene {
  Mesh mesh;
  std::vector<std::int32_t> object;
};

// An icosphere, a box and a floor quad, all moved by `offset` (the camera must move with it).
// Throws InputError if the scene would leave the supported range (check_supported_range).
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
