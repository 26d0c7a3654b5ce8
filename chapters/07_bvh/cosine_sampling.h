// Chapter 07: cosine-weighted directions about a surface normal, which the benchmark protocol
// gives its ao and diffuse rays (protocol.h) and chapter 11's path tracer its bounces. They are
// the same bits on the CPU and the GPU: the sine and cosine are the course's own, and nothing
// here is fused into an FMA on either side.
#pragma once

#include <cmath>

#include "rt/hd.h"
#include "rt/vec.h"

// Every float operation below must be rounded on its own: nvcc fuses a*b + c into one FMA by
// default, and a fused Duff basis or hit point differs in its last bits, enough to flip a tiny
// normal component on an axis-aligned wall and send a whole ray elsewhere. The host compiler
// does not fuse (the C++ files are built with -ffp-contract=off, and nvcc's host side has no
// FMA at x86-64's baseline). On the device these functions exist only in translation units
// built with -fmad=false that define RT_NO_CONTRACTION (chapter 07's protocol_gpu.cu, chapter
// 11's kernels). Anywhere else they are host functions, so calling one from a kernel built
// with nvcc's default flags is a compile error instead of a silent difference.
#if defined(RT_NO_CONTRACTION) && defined(__CUDACC__)
#define RT_UNFUSED_HD __host__ __device__
#else
#define RT_UNFUSED_HD
#endif

namespace rt::ch07 {

struct SinCos {
  float sin, cos;
};

// sin and cos of 2 pi turns, for turns in [0, 1). The GPU's sinf and cosf (2 ulps) and the C
// library's round differently, so the same pixel would get a different direction on each
// backend; plain adds and multiplies round alike everywhere. turns * 4 splits exactly into a
// quadrant k and a remainder f in [-1/2, 1/2]; the angle f pi/2 then lies in [-pi/4, pi/4],
// where the short minimax polynomials of Cephes' sinf and cosf (Moshier) are good to ~1 ulp.
RT_UNFUSED_HD inline SinCos sin_cos_turns(float turns) {
  const float quarter_turns = turns * 4.0f;
  const float k = rintf(quarter_turns);
  constexpr float k_half_pi = 1.57079637f;         // pi/2 rounded to float
  const float x = (quarter_turns - k) * k_half_pi; // the angle left over, in radians
  const float z = x * x;
  constexpr float k_s1 = -1.6666654611e-1f, k_s2 = 8.3321608736e-3f, k_s3 = -1.9515295891e-4f;
  constexpr float k_c1 = 4.166664568e-2f, k_c2 = -1.388731625e-3f, k_c3 = 2.443315712e-5f;
  // The small terms first, as Cephes sums them: x (or 1) is added last.
  const float s = z * x * (k_s1 + z * (k_s2 + z * k_s3)) + x;
  const float c = z * z * (k_c1 + z * (k_c2 + z * k_c3)) - 0.5f * z + 1.0f;
  switch (static_cast<int>(k) & 3) { // each quarter turn rotates (cos, sin) by 90 degrees
  case 0:
    return {s, c};
  case 1:
    return {c, -s};
  case 2:
    return {-s, -c};
  default:
    return {-c, s};
  }
}

// Two unit vectors that make a right-handed orthonormal frame with the unit normal n
// (cross(tangent, bitangent) = n).
struct TangentFrame {
  Vec3f tangent, bitangent;
};

// [listing:cosine_direction]
// Duff et al. 2017, "Building an Orthonormal Basis, Revisited": Frisvad's branch-free frame,
// with copysign choosing the formula that stays accurate on each side of n.z = 0 (the original
// divided by 1 + n.z and lost every digit near n = (0, 0, -1)).
RT_UNFUSED_HD inline TangentFrame duff_frame(Vec3f n) {
  const float sign = copysignf(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return {{1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x},
          {b, sign + n.y * n.y * a, -n.y}};
}

// A direction about +z with density cos(theta) / pi (Malley's method: a uniform point on the
// unit disk, lifted to the hemisphere); its z is cos(theta). u1 and u2 are uniform in [0, 1).
RT_UNFUSED_HD inline Vec3f cosine_direction_about_z(float u1, float u2) {
  const float s = sqrtf(u1); // the disk radius; u1 < 1, so 1 - u1 is exact and positive
  const SinCos phi = sin_cos_turns(u2);
  return {s * phi.cos, s * phi.sin, sqrtf(1.0f - u1)};
}

// A direction given about +z turned to the unit normal n, through n's Duff frame.
RT_UNFUSED_HD inline Vec3f turn_to_normal(Vec3f n, Vec3f local) {
  const TangentFrame frame = duff_frame(n);
  return normalize(local.x * frame.tangent + local.y * frame.bitangent + local.z * n);
}

// The same density about the unit normal n.
RT_UNFUSED_HD inline Vec3f cosine_direction(Vec3f n, float u1, float u2) {
  return turn_to_normal(n, cosine_direction_about_z(u1, u2));
}
// [/listing:cosine_direction]

} // namespace rt::ch07
