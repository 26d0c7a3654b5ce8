// Chapter 04: rays against a mesh, brute force, on either backend. See triangles.h.
#include "triangles.h"

#include <span>

#include "ray_batch.h"
#include "rt/device_buffer.h"

namespace rt::ch04 {

using ch03::for_each_ray_cpu;
using ch03::for_each_ray_gpu;

const char* to_string(TriangleVariant variant) {
  return variant == TriangleVariant::moller_trumbore ? "Moller-Trumbore" : "watertight";
}

namespace {

// The mesh in device memory for as long as this object lives.
struct DeviceMesh {
  DeviceBuffer<Vec3f> vertices;
  DeviceBuffer<IndexedTriangle> triangles;

  explicit DeviceMesh(const Mesh& mesh)
      : vertices(std::span<const Vec3f>(mesh.vertices)),
        triangles(std::span<const IndexedTriangle>(mesh.triangles)) {}
  MeshView view() const {
    return {vertices.data(), triangles.data(), static_cast<int>(triangles.size())};
  }
};

// What the tallies of a batch of rays add up to.
LeakCount count_tallies(const std::vector<HitTally>& tallies) {
  LeakCount count;
  count.rays = static_cast<long long>(tallies.size());
  for (const HitTally& tally : tallies) {
    count.leaks += tally.hits == 0 ? 1 : 0;
    count.double_hits += tally.hits >= 2 ? 1 : 0;
    count.non_finite += tally.non_finite > 0 ? 1 : 0;
  }
  return count;
}

} // namespace

std::vector<MeshHit> closest_hits_gpu(TriangleVariant variant, const Mesh& mesh,
                                      const std::vector<RayF>& rays) {
  const DeviceMesh d_mesh(mesh);
  const DeviceBuffer<RayF> d_rays{std::span<const RayF>(rays)};
  DeviceBuffer<MeshHit> d_hits(rays.size());
  const MeshView view = d_mesh.view();
  const RayF* ray_in = d_rays.data();
  MeshHit* hit_out = d_hits.data();
  for_each_ray_gpu(static_cast<int>(rays.size()), [=] __device__(int i) {
    hit_out[i] = closest_hit(variant, view, ray_in[i]);
  });
  return d_hits.to_host();
}

std::vector<MeshHit> closest_hits_cpu(TriangleVariant variant, const Mesh& mesh,
                                      const std::vector<RayF>& rays) {
  std::vector<MeshHit> hits(rays.size());
  const MeshView view = host_view(mesh);
  for_each_ray_cpu(static_cast<int>(rays.size()),
                   [&](int i) { hits[i] = closest_hit(variant, view, rays[i]); });
  return hits;
}

DeviceLeakTest::DeviceLeakTest(const Mesh& mesh, const std::vector<RayF>& rays)
    : vertices_(std::span<const Vec3f>(mesh.vertices)),
      triangles_(std::span<const IndexedTriangle>(mesh.triangles)),
      rays_(std::span<const RayF>(rays)), tallies_(rays.size()) {}

void DeviceLeakTest::launch(TriangleVariant variant) {
  const MeshView view{vertices_.data(), triangles_.data(), static_cast<int>(triangles_.size())};
  const RayF* ray_in = rays_.data();
  HitTally* tally_out = tallies_.data();
  for_each_ray_gpu(static_cast<int>(rays_.size()), [=] __device__(int i) {
    tally_out[i] = tally_hits(variant, view, ray_in[i]);
  });
}

LeakCount DeviceLeakTest::count() const { return count_tallies(tallies_.to_host()); }

LeakCount count_leaks_gpu(TriangleVariant variant, const Mesh& mesh,
                          const std::vector<RayF>& rays) {
  DeviceLeakTest test(mesh, rays);
  test.launch(variant);
  return test.count();
}

std::vector<HitTally> tally_hits_cpu(TriangleVariant variant, const Mesh& mesh,
                                     const std::vector<RayF>& rays) {
  std::vector<HitTally> tallies(rays.size());
  const MeshView view = host_view(mesh);
  for_each_ray_cpu(static_cast<int>(rays.size()),
                   [&](int i) { tallies[i] = tally_hits(variant, view, rays[i]); });
  return tallies;
}

LeakCount count_leaks_cpu(TriangleVariant variant, const Mesh& mesh,
                          const std::vector<RayF>& rays) {
  return count_tallies(tally_hits_cpu(variant, mesh, rays));
}

} // namespace rt::ch04
