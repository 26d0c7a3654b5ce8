// Chapter 03 test cases shared by the CPU and GPU tests: rays that graze a small sphere far
// away, rays from an eye just above a huge "ground" sphere, and their float64 references.
#pragma once

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "ray.h"
#include "sphere.h"

namespace rt::testing {

using ch03::RayF;
using ch03::SphereF;

// Distance from the sphere's centre to the ray's line, in float64 from the float inputs: the
// reference says "hit" iff this is below the radius (the sphere lies ahead of every ray here).
inline double distance_to_ray_line(RayF ray, SphereF sphere) {
  const Vec3d d = ray.direction.as<double>();
  const Vec3d f = ray.origin.as<double>() - sphere.centre.as<double>();
  const Vec3d along = d * (dot(f, d) / dot(d, d));
  return length(f - along);
}

// How far from the silhouette the float stable test may misjudge a ray. Its perpendicular
// vector l = f + (beta/a) d is a sum of terms of size D = |o - c|, so it carries rounding
// errors of a few ulps of D (an ulp of D is at most one float epsilon times D). Measured over
// 900k rays at 1e3..1e5 radii, the worst misjudged ray passed 0.16 epsilons of D from the
// silhouette; the band is 2 epsilons of D (plus the radius, for spheres close by).
inline double stable_silhouette_band(RayF ray, SphereF sphere) {
  const double distance = length(ray.origin.as<double>() - sphere.centre.as<double>());
  return 2.0 * std::numeric_limits<float>::epsilon() * (distance + sphere.radius);
}

// A unit sphere seen from `distance_in_radii` away, and rays from one eye aimed at points
// between 0.5 and 1.5 radii from its centre across the line of sight: half of them graze it.
struct FarSphereCase {
  SphereF sphere;
  std::vector<RayF> rays;
};

inline FarSphereCase far_sphere_case(float distance_in_radii, int ray_count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), spread(0.5f, 1.5f);
  const SphereF sphere{{0.25f, -0.5f, 0.75f}, 1.0f};
  const Vec3f view = normalize(Vec3f{0.3f, 0.2f, -1.0f});
  const Vec3f eye = sphere.centre - view * distance_in_radii;
  FarSphereCase result{sphere, {}};
  result.rays.reserve(ray_count);
  while (static_cast<int>(result.rays.size()) < ray_count) {
    const Vec3f random{unit(rng), unit(rng), unit(rng)};
    const Vec3f across = random - view * dot(random, view); // perpendicular to the view
    if (!(length(across) > 0.1f)) continue;
    const Vec3f target = sphere.centre + normalize(across) * (sphere.radius * spread(rng));
    result.rays.push_back(RayF{eye, target - eye});
  }
  return result;
}

// A sphere of radius R centred at the world origin (so o - c is exact) and an eye 1 to 10
// units above its north pole, looking down at points of the "ground" within 10 eye heights:
// rays at least 1/10 rad below the horizontal, away from the ill-conditioned horizon.
struct GroundSphereCase {
  SphereF sphere;
  std::vector<RayF> rays;
};

inline GroundSphereCase ground_sphere_case(float radius, int ray_count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> height(1.0f, 10.0f), unit(-1.0f, 1.0f);
  GroundSphereCase result{{{0.0f, 0.0f, 0.0f}, radius}, {}};
  result.rays.reserve(ray_count);
  while (static_cast<int>(result.rays.size()) < ray_count) {
    const float h = height(rng);
    const Vec3f eye{unit(rng), radius + h, unit(rng)};
    const float across_x = 10.0f * h * unit(rng), across_z = 10.0f * h * unit(rng);
    if (!(across_x * across_x + across_z * across_z <= 100.0f * h * h)) continue;
    const Vec3f ground{eye.x + across_x, radius, eye.z + across_z};
    result.rays.push_back(RayF{eye, normalize(ground - eye)});
  }
  return result;
}

} // namespace rt::testing
