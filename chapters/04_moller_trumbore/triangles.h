// Chapter 04 on both backends: a batch of rays against every triangle of a mesh (brute force),
// the closest hit of each ray, and the leak count of rays fired from inside a closed mesh.
#pragma once

#include <limits>
#include <vector>

#include "mesh_gen.h"
#include "mesh_hit.h"
#include "rt/device_buffer.h"
#include "triangle.h"

namespace rt::ch04 {

using ch03::RayF;

enum class TriangleVariant { moller_trumbore, watertight };

const char* to_string(TriangleVariant variant);

template <class T>
RT_HD inline TriangleHit<T> intersect_triangle(TriangleVariant variant, Ray<T> ray,
                                               Triangle<T> tri) {
  return variant == TriangleVariant::moller_trumbore ? intersect_moller_trumbore(ray, tri)
                                                     : intersect_watertight(ray, tri);
}

// The mesh as per-ray code reads it: host pointers on the CPU, device pointers on the GPU.
struct MeshView {
  const Vec3f* vertices;            // shared by the triangles
  const IndexedTriangle* triangles; // three indices into vertices each
  int triangle_count;

  RT_HD TriangleF triangle(int i) const {
    const IndexedTriangle t = triangles[i];
    return {vertices[t.v0], vertices[t.v1], vertices[t.v2]};
  }
};

// A view of a mesh in host memory, for the CPU backend.
inline MeshView host_view(const Mesh& mesh) {
  return {mesh.vertices.data(), mesh.triangles.data(), static_cast<int>(mesh.triangles.size())};
}

// Every triangle, keeping the nearest hit: tmax shrinks as hits are found.
RT_HD inline MeshHit closest_hit(TriangleVariant variant, MeshView mesh, RayF ray) {
  MeshHit closest;
  for (int i = 0; i < mesh.triangle_count; ++i) {
    const TriangleHitF hit = intersect_triangle(variant, ray, mesh.triangle(i));
    if (hit.hit) {
      closest = {hit.t, i};
      ray.tmax = hit.t;
    }
  }
  return closest;
}

// How many triangles accept the ray: 0 from inside a closed mesh is a leak, 2 or more (at a
// shared edge or vertex) a double hit. An accepted hit whose t, u or v is not finite would
// poison whatever shades it: those are counted too.
struct HitTally {
  int hits = 0;
  int non_finite = 0;
};

RT_HD inline HitTally tally_hits(TriangleVariant variant, MeshView mesh, RayF ray) {
  HitTally tally;
  for (int i = 0; i < mesh.triangle_count; ++i) {
    const TriangleHitF hit = intersect_triangle(variant, ray, mesh.triangle(i));
    if (!hit.hit) continue;
    ++tally.hits;
    if (!is_finite(hit.t) || !is_finite(hit.u) || !is_finite(hit.v)) ++tally.non_finite;
  }
  return tally;
}

struct LeakCount {
  long long rays = 0;        // rays fired from inside
  long long leaks = 0;       // rays no triangle accepted
  long long double_hits = 0; // rays two or more triangles accepted
  long long non_finite = 0;  // rays with an accepted hit whose t, u or v is NaN or infinite
};

std::vector<MeshHit> closest_hits_gpu(TriangleVariant variant, const Mesh& mesh,
                                      const std::vector<RayF>& rays);
std::vector<MeshHit> closest_hits_cpu(TriangleVariant variant, const Mesh& mesh,
                                      const std::vector<RayF>& rays);

// The leak test on the GPU, in steps, so that the kernel alone can be timed: the mesh and the
// rays are uploaded once, each launch writes one tally per ray in device memory, and count()
// copies the tallies of the last launch back.
class DeviceLeakTest {
public:
  DeviceLeakTest(const Mesh& mesh, const std::vector<RayF>& rays);
  void launch(TriangleVariant variant); // queues the kernel only: no allocation, no copy
  LeakCount count() const;

private:
  DeviceBuffer<Vec3f> vertices_;
  DeviceBuffer<IndexedTriangle> triangles_;
  DeviceBuffer<RayF> rays_;
  DeviceBuffer<HitTally> tallies_;
};

LeakCount count_leaks_gpu(TriangleVariant variant, const Mesh& mesh,
                          const std::vector<RayF>& rays);
// Every ray's tally (the picture of where rays leak needs them one by one), and their count.
std::vector<HitTally> tally_hits_cpu(TriangleVariant variant, const Mesh& mesh,
                                     const std::vector<RayF>& rays);
LeakCount count_leaks_cpu(TriangleVariant variant, const Mesh& mesh,
                          const std::vector<RayF>& rays);

} // namespace rt::ch04
