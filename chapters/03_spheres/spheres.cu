// Chapter 03: one sphere against a batch of rays on either backend. See spheres.h.
#include "spheres.h"

#include "ray_batch.h"
#include "rt/device_buffer.h"

namespace rt::ch03 {

const char* to_string(SphereVariant variant) {
  return variant == SphereVariant::textbook ? "textbook quadratic" : "stable quadratic";
}

std::vector<RayF> pinhole_rays_gpu(const PinholeCamera<float>& camera) {
  const int width = camera.width;
  DeviceBuffer<RayF> d_rays(static_cast<std::size_t>(width) * camera.height);
  RayF* ray_out = d_rays.data();
  for_each_ray_gpu(static_cast<int>(d_rays.size()), [=] __device__(int i) {
    ray_out[i] = camera.ray_through_pixel(i % width, i / width);
  });
  return d_rays.to_host();
}

std::vector<RayF> pinhole_rays_cpu(const PinholeCamera<float>& camera) {
  const int width = camera.width;
  std::vector<RayF> rays(static_cast<std::size_t>(width) * camera.height);
  for_each_ray_cpu(static_cast<int>(rays.size()),
                   [&](int i) { rays[i] = camera.ray_through_pixel(i % width, i / width); });
  return rays;
}

std::vector<SphereHitF> intersect_spheres_gpu(SphereVariant variant,
                                              const std::vector<RayF>& rays, SphereF sphere) {
  const int count = static_cast<int>(rays.size());
  const DeviceBuffer<RayF> d_rays{std::span<const RayF>(rays)};
  DeviceBuffer<SphereHitF> d_hits(rays.size());
  const RayF* ray_in = d_rays.data();
  SphereHitF* hit_out = d_hits.data();
  for_each_ray_gpu(count, [=] __device__(int i) {
    hit_out[i] = intersect_sphere(variant, ray_in[i], sphere);
  });
  return d_hits.to_host();
}

std::vector<SphereHitF> intersect_spheres_cpu(SphereVariant variant,
                                              const std::vector<RayF>& rays, SphereF sphere) {
  std::vector<SphereHitF> hits(rays.size());
  for_each_ray_cpu(static_cast<int>(rays.size()),
                   [&](int i) { hits[i] = intersect_sphere(variant, rays[i], sphere); });
  return hits;
}

} // namespace rt::ch03
