// Chapter 03 on both backends: a camera's primary rays, and one sphere against a batch of rays
// with either intersection variant, on the GPU or the CPU through the same per-ray functions.
#pragma once

#include <vector>

#include "camera.h"
#include "ray.h"
#include "sphere.h"

namespace rt::ch03 {

enum class SphereVariant { textbook, stable };

const char* to_string(SphereVariant variant);

template <class T>
RT_HD inline SphereHit<T> intersect_sphere(SphereVariant variant, Ray<T> ray,
                                           Sphere<T> sphere) {
  return variant == SphereVariant::textbook ? intersect_sphere_textbook(ray, sphere)
                                            : intersect_sphere_stable(ray, sphere);
}

// The ray through every pixel, row-major: rays[j * width + i].
std::vector<RayF> pinhole_rays_gpu(const PinholeCamera<float>& camera);
std::vector<RayF> pinhole_rays_cpu(const PinholeCamera<float>& camera);

// hits[i] is the nearest hit of rays[i] with the sphere.
std::vector<SphereHitF> intersect_spheres_gpu(SphereVariant variant,
                                              const std::vector<RayF>& rays, SphereF sphere);
std::vector<SphereHitF> intersect_spheres_cpu(SphereVariant variant,
                                              const std::vector<RayF>& rays, SphereF sphere);

} // namespace rt::ch03
