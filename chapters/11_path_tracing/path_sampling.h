// Chapter 11: the sampling a Lambertian path tracer needs: an orthonormal basis around a
// normal, cosine-weighted directions, uniform points on triangles, and the power heuristic
// that weights two strategies for the same light (Veach 1997, chapter 9).
#pragma once

#include <cmath>
#include <numbers>

#include "rt/scalar.h"
#include "rt/vec.h"

namespace rt::ch11 {

inline constexpr float k_pi = std::numbers::pi_v<float>;

// Two unit vectors that make a right-handed frame with the unit normal n, without a branch
// on which axis n is nearest (Duff et al. 2017, "Building an orthonormal basis, revisited").
struct Frame {
  Vec3f tangent, bitangent, normal;
  RT_HD Vec3f to_world(Vec3f local) const {
    return tangent * local.x + bitangent * local.y + normal * local.z;
  }
};

RT_HD inline Frame frame_around(Vec3f n) {
  const float sign = n.z >= 0.0f ? 1.0f : -1.0f;
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return {
      {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x}, {b, sign + n.y * n.y * a, -n.y}, n};
}

// [listing:cosine_sample]
// A direction about +z with density cos(theta) / pi: a uniform point on the unit disc
// (radius sqrt(u), angle 2 pi v) lifted onto the hemisphere (Malley's method). For a
// Lambertian surface of albedo a, f cos / pdf = (a / pi) cos / (cos / pi) = a: every sample
// carries the albedo and nothing else.
RT_HD inline Vec3f cosine_direction(float u, float v) {
  const float r = square_root(u);
  float sine, cosine;
#if RT_ON_DEVICE
  sincospif(2.0f * v, &sine, &cosine); // sin(pi x), without cosf's slow path for huge x
#else
  sine = std::sin(2.0f * k_pi * v);
  cosine = std::cos(2.0f * k_pi * v);
#endif
  return {r * cosine, r * sine, square_root(max_of(0.0f, 1.0f - u))};
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
