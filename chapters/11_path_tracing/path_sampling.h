// Chapter 11: the sampling a Lambertian path tracer needs: cosine-weighted directions (chapter
// 07's), uniform points on triangles, and the power heuristic that weights two strategies for
// the same light (Veach 1997, chapter 9).
#pragma once

#include <numbers>

#include "cosine_sampling.h"
#include "rt/scalar.h"
#include "rt/vec.h"

namespace rt::ch11 {

inline constexpr float k_pi = std::numbers::pi_v<float>;

// The density per solid angle of a cosine-weighted direction at angle theta to the normal:
// cos(theta) / pi above the surface, nothing below it.
RT_HD inline float cosine_density(float cosine) { return cosine > 0.0f ? cosine / k_pi : 0.0f; }

// A direction drawn by a sampler and its density per solid angle.
struct DirectionSample {
  Vec3f direction; // unit
  float pdf;
};

// [listing:cosine_sample]
// The bounce of a Lambertian surface: chapter 07's cosine-weighted direction about the unit
// normal n, the protocol's secondary rays (Duff's frame, Malley's method, the course's own
// sine and cosine), so the CPU and the GPU draw the same bits. For a surface of albedo a,
// f cos / pdf = (a / pi) cos / (cos / pi) = a: every sample carries the albedo and nothing
// else.
RT_UNFUSED_HD inline DirectionSample sample_cosine(Vec3f n, float u, float v) {
  const Vec3f local = ch07::cosine_direction_about_z(u, v); // its z is cos(theta)
  return {ch07::turn_to_normal(n, local), cosine_density(local.z)};
}
// [/listing:cosine_sample]

// A uniform point on a triangle from two numbers in [0, 1): the square root folds the unit
// square onto the triangle without bunching at a corner.
RT_HD inline Vec3f point_on_triangle(Vec3f v0, Vec3f v1, Vec3f v2, float u, float v) {
  const float s = square_root(u);
  const float b0 = 1.0f - s, b1 = v * s;
  return v0 * b0 + v1 * b1 + v2 * (1.0f - b0 - b1);
}

// [listing:power_heuristic]
// The weight of a sample drawn by strategy A (density pdf_a) when strategy B (pdf_b) could
// have drawn it too: the power heuristic with exponent 2. The weights of the two strategies
// for one direction add to 1, so the sum stays unbiased, and each strategy gets the
// directions it samples well.
RT_HD inline float power_heuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}
// [/listing:power_heuristic]

// The brightness of a colour as the eye weights it (Rec. 709 luminance): what the light
// table weights emitters by.
RT_HD inline float luminance(Vec3f c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

} // namespace rt::ch11
