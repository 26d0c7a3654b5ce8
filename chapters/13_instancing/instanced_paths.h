// Chapter 13: the two levels under chapter 11's path tracing. A sky-lit Lambertian path per
// sample: the camera ray and every bounce traced through both levels, each bounce drawn by
// chapter 11's cosine-weighted sampler from chapter 11's stateless random numbers, Russian
// roulette from the fourth surface on, and the sky's radiance where a path leaves the scene.
// With every albedo 1 under a sky of 1 (a white furnace) every pixel's exact value is 1,
// whatever the instances and their transforms: what the tests check.
#pragma once

#include "rt/backend.h"
#include "rt/image.h"
#include "rt/launch.h"
#include "two_level_scene.h"

namespace rt::ch13 {

struct PathSettings {
  int samples = 16; // per pixel
  Vec3f sky{1.0f, 1.0f, 1.0f};
  bool white = false; // every albedo 1 (the white furnace)
  unsigned first_sample = 0;
};

// Each pixel's mean radiance over settings.samples paths into `radiance` and its picture into
// `pixels` (backend pointers, width * height each; `pixels` may be null).
void render_paths(const TwoLevelScene& scene, const ch03::Camera<float>& camera, Extent extent,
                  const PathSettings& settings, Vec3f* radiance, Rgba8* pixels);

} // namespace rt::ch13
