// Chapter 09: walking a wide tree. One RT_HD function for both backends, every wide layout and
// both queries. Each node read tests the ray against all its children's boxes at once and
// turns the result into a 32-bit hit mask: interior children in the high byte, ordered for the
// ray's octant, triangles in the low 24 bits. The stack holds such masks, not single nodes.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "traverse.h"
#include "wide_bvh.h"

#if !defined(__CUDA_ARCH__) && defined(__AVX2__)
#include <immintrin.h>
#endif

namespace rt::ch09 {

using ch03::RayF;
using ch07::Query;
using ch07::TraceHit;

// What every node test of one ray shares: chapter 07's box ray (origin, 1/direction and the
// signs that pick each axis's near plane) and the ray's octant, inverted. The same 32 bytes on
// both backends and under every compile flag: the CPU's eight-lane form of the ray is a type
// of its own (WideRayAvx2, below), which the scalar code never sees.
struct WideRay {
  ch07::BoxRay box;
  unsigned octant_inverse; // 7 - octant, octant bit k set where 1/direction_k < 0
};
static_assert(sizeof(ch07::BoxRay) == 28 && sizeof(WideRay) == 32 &&
                  offsetof(WideRay, octant_inverse) == 28,
              "one layout of WideRay for every compiler and flag that builds the course");

RT_INLINE_ON_CPU RT_HD inline WideRay make_wide_ray(const RayF& ray) {
  const ch07::BoxRay box = ch07::make_box_ray(ray);
  const unsigned octant =
      (box.negative[0] ? 1u : 0u) | (box.negative[1] ? 2u : 0u) | (box.negative[2] ? 4u : 0u);
  return {box, 7u - octant};
}

// The planes of N child boxes, nearer plane and farther plane per axis for this ray's signs.
template <int N> struct ChildSlabs {
  float near_x[N], near_y[N], near_z[N];
  float far_x[N], far_y[N], far_z[N];
};

// The near and far planes picked from boxes stored by coordinate: per axis, a ray going the
// negative way enters at hi and leaves at lo. The choice is the same for every child (one
// select per value, no branch).
template <int N>
RT_HD inline ChildSlabs<N> pick_slabs(const float (&lo_x)[N], const float (&lo_y)[N],
                                      const float (&lo_z)[N], const float (&hi_x)[N],
                                      const float (&hi_y)[N], const float (&hi_z)[N],
                                      const WideRay& r) {
  const bool nx = r.box.negative[0], ny = r.box.negative[1], nz = r.box.negative[2];
  ChildSlabs<N> s;
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
  for (int c = 0; c < N; ++c) {
    s.near_x[c] = nx ? hi_x[c] : lo_x[c];
    s.near_y[c] = ny ? hi_y[c] : lo_y[c];
    s.near_z[c] = nz ? hi_z[c] : lo_z[c];
    s.far_x[c] = nx ? lo_x[c] : hi_x[c];
    s.far_y[c] = ny ? lo_y[c] : hi_y[c];
    s.far_z[c] = nz ? lo_z[c] : hi_z[c];
  }
  return s;
}

template <int N> RT_HD inline ChildSlabs<N> slabs_of(const WideNode<N>& n, const WideRay& r) {
  return pick_slabs(n.lo_x, n.lo_y, n.lo_z, n.hi_x, n.hi_y, n.hi_z, r);
}

// [listing:compressed_slabs]
// The compressed node's child boxes back in float: every grid coordinate dequantised (one loop
// per coordinate, so the CPU converts and scales eight at once). The float planes are exactly
// the build's (dequantise), so each box tested contains its child's exact box.
struct ChildPlanes {
  float lo_x[k_slots], lo_y[k_slots], lo_z[k_slots];
  float hi_x[k_slots], hi_y[k_slots], hi_z[k_slots];
};

RT_HD inline ChildPlanes dequantise_planes(const CompressedNode& n) {
  const float sx = grid_step(n.exponent[0]), sy = grid_step(n.exponent[1]),
              sz = grid_step(n.exponent[2]);
  ChildPlanes p;
  RT_UNROLL
  for (int c = 0; c < k_slots; ++c) {
    p.lo_x[c] = dequantise(n.q_lo_x[c], sx, n.origin[0]);
    p.lo_y[c] = dequantise(n.q_lo_y[c], sy, n.origin[1]);
    p.lo_z[c] = dequantise(n.q_lo_z[c], sz, n.origin[2]);
    p.hi_x[c] = dequantise(n.q_hi_x[c], sx, n.origin[0]);
    p.hi_y[c] = dequantise(n.q_hi_y[c], sy, n.origin[1]);
    p.hi_z[c] = dequantise(n.q_hi_z[c], sz, n.origin[2]);
  }
  return p;
}

// Then the near and far planes picked as for float boxes.
RT_HD inline ChildSlabs<k_slots> slabs_of(const CompressedNode& n, const WideRay& r) {
  const ChildPlanes p = dequantise_planes(n);
  return pick_slabs(p.lo_x, p.lo_y, p.lo_z, p.hi_x, p.hi_y, p.hi_z, r);
}
// [/listing:compressed_slabs]

// Chapter 07's exit widening, 1 + 2 gamma(3) (Ize 2013): each slab distance below is computed
// with the same two rounded operations from the same rounded 1/d as chapter 07's enter_box.
inline constexpr float k_exit_widening =
    1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

// [listing:child_test]
// Chapter 07's slab test for N boxes at once: bit c of the result is set where the ray enters
// child c within [tmin, tmax]. The same arithmetic as enter_box, box by box, so the same
// robustness argument: NaN from 0 * inf is ignored (an origin on a slab plane counts as inside)
// and the exit distance is widened, so a ray that touches a box in exact arithmetic is never
// refused; tmax is widened by chapter 07's k_tmax_slack, so no box of a triangle the
// triangle test hits before tmax is refused either. The loop has no branches and reads the
// planes by coordinate; on the GPU it is unrolled. The CPU runs enter_children_cpu (below),
// the same arithmetic arranged for its vector units.
template <int N>
RT_HD inline unsigned enter_children(const ChildSlabs<N>& s, const ch07::BoxRay& r, float tmin,
                                     float tmax) {
  using ch07::max_ignoring_nan;
  using ch07::min_ignoring_nan;
  const float tmax_kept = tmax * ch07::k_tmax_slack; // chapter 07's slack on the nearest hit
  bool entered[N];
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
  for (int c = 0; c < N; ++c) {
    const float near_x = (s.near_x[c] - r.origin.x) * r.inverse.x;
    const float near_y = (s.near_y[c] - r.origin.y) * r.inverse.y;
    const float near_z = (s.near_z[c] - r.origin.z) * r.inverse.z;
    const float far_x = (s.far_x[c] - r.origin.x) * r.inverse.x;
    const float far_y = (s.far_y[c] - r.origin.y) * r.inverse.y;
    const float far_z = (s.far_z[c] - r.origin.z) * r.inverse.z;
    const float t_enter =
        max_ignoring_nan(max_ignoring_nan(near_x, near_y), max_ignoring_nan(near_z, tmin));
    const float t_exit =
        min_ignoring_nan(min_ignoring_nan(far_x, far_y), far_z) * k_exit_widening;
    entered[c] = t_enter <= min_ignoring_nan(t_exit, tmax_kept);
  }
  unsigned mask = 0;
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
  for (int c = 0; c < N; ++c) mask |= unsigned(entered[c]) << c;
  return mask;
}
// [/listing:child_test]

#if !defined(__CUDA_ARCH__)
// [listing:child_test_cpu]
// The same test on the CPU, the same arithmetic arranged for its vector units: one loop whose
// every step the compiler turns into one instruction over all N children (8 floats fill one
// AVX register), with no branch.
//   - Each axis's near and far planes are chosen once per node, as whole arrays, not child by
//     child.
//   - `a > acc ? a : acc` is x86's own max (maxps: where a is NaN the comparison fails and acc
//     wins). With the accumulator second, starting from tmin (or +inf for the exit), which is
//     never NaN, a NaN distance is ignored exactly as max_ignoring_nan ignores it, with no
//     extra compare: child for child the same answer as enter_children.
//   - The answers go to an array and become the bit mask in a second loop: a loop that mixes
//     floats with mask bits is one the compiler leaves scalar. (GCC still gathers that mask
//     lane by lane; with AVX2, node_bits_avx2 below takes it in one instruction.)
inline float max_onto(float a, float acc) { return a > acc ? a : acc; }
inline float min_onto(float a, float acc) { return a < acc ? a : acc; }

//   - Each child's entry distance goes to `t_enter` as well, for the traversal that orders
//     children by distance (cpu_traverse.h); the others pass an array nobody reads.
template <int N>
RT_INLINE_ON_CPU inline unsigned
enter_children_cpu(const float (&lo_x)[N], const float (&lo_y)[N], const float (&lo_z)[N],
                   const float (&hi_x)[N], const float (&hi_y)[N], const float (&hi_z)[N],
                   const ch07::BoxRay& r, float tmin, float tmax, float (&t_enter)[N]) {
  const float* near_x = r.negative[0] ? hi_x : lo_x;
  const float* near_y = r.negative[1] ? hi_y : lo_y;
  const float* near_z = r.negative[2] ? hi_z : lo_z;
  const float* far_x = r.negative[0] ? lo_x : hi_x;
  const float* far_y = r.negative[1] ? lo_y : hi_y;
  const float* far_z = r.negative[2] ? lo_z : hi_z;
  const float tmax_kept = tmax * ch07::k_tmax_slack;
  const float infinity = std::numeric_limits<float>::infinity();
  int entered[N];
  for (int c = 0; c < N; ++c) {
    t_enter[c] = max_onto((near_z[c] - r.origin.z) * r.inverse.z,
                          max_onto((near_y[c] - r.origin.y) * r.inverse.y,
                                   max_onto((near_x[c] - r.origin.x) * r.inverse.x, tmin)));
    const float t_exit =
        min_onto((far_z[c] - r.origin.z) * r.inverse.z,
                 min_onto((far_y[c] - r.origin.y) * r.inverse.y,
                          min_onto((far_x[c] - r.origin.x) * r.inverse.x, infinity))) *
        k_exit_widening;
    entered[c] = t_enter[c] <= min_onto(t_exit, tmax_kept) ? -1 : 0;
  }
  unsigned mask = 0;
  for (int c = 0; c < N; ++c) mask |= unsigned(entered[c]) & (1u << c);
  return mask;
}
// [/listing:child_test_cpu]

template <int N>
RT_INLINE_ON_CPU inline unsigned enter_children_cpu(const WideNode<N>& n, const WideRay& r,
                                                    float tmin, float tmax) {
  float t_enter[N];
  return enter_children_cpu(n.lo_x, n.lo_y, n.lo_z, n.hi_x, n.hi_y, n.hi_z, r.box, tmin, tmax,
                            t_enter);
}

// The compressed node's planes dequantised first (dequantise_planes), then the same test.
RT_INLINE_ON_CPU inline unsigned enter_children_cpu(const CompressedNode& n, const WideRay& r,
                                                    float tmin, float tmax) {
  const ChildPlanes p = dequantise_planes(n);
  float t_enter[k_slots];
  return enter_children_cpu(p.lo_x, p.lo_y, p.lo_z, p.hi_x, p.hi_y, p.hi_z, r.box, tmin, tmax,
                            t_enter);
}

#if defined(__AVX2__)
// On a CPU with AVX2: the ray broadcast over the eight lanes of a vector register, and the
// byte offsets of each axis's near and far planes in a node's six plane arrays (lo_x lo_y lo_z
// hi_x hi_y hi_z, 8 floats each), which the ray's signs pick. Made once per ray, for the
// eight-wide node reads (node_bits_avx2, below).
struct EightLaneRay {
  __m256 origin_x, origin_y, origin_z, inverse_x, inverse_y, inverse_z;
  __m256i octant_inverse;
  int near_x, near_y, near_z, far_x, far_y, far_z;
};

RT_INLINE_ON_CPU inline EightLaneRay make_eight_lane_ray(const WideRay& r) {
  constexpr int k_array = 8 * sizeof(float), k_hi = 3 * k_array; // bytes
  const auto near = [&](int axis) {
    return axis * k_array + (r.box.negative[axis] ? k_hi : 0);
  };
  const auto far = [&](int axis) { return axis * k_array + (r.box.negative[axis] ? 0 : k_hi); };
  return {_mm256_set1_ps(r.box.origin.x),
          _mm256_set1_ps(r.box.origin.y),
          _mm256_set1_ps(r.box.origin.z),
          _mm256_set1_ps(r.box.inverse.x),
          _mm256_set1_ps(r.box.inverse.y),
          _mm256_set1_ps(r.box.inverse.z),
          _mm256_set1_epi32(int(r.octant_inverse)),
          near(0),
          near(1),
          near(2),
          far(0),
          far(1),
          far(2)};
}

// What the CPU's traversal carries where AVX2 is compiled: the ray as every node read takes it
// and its eight lanes, which only the eight-wide node reads below use.
struct WideRayAvx2 : WideRay {
  EightLaneRay lanes;
};

// [listing:node_avx2]
// Where the CPU has AVX2 (RT_CPU_ARCH=native on such a machine), the whole node test of an
// eight-wide node is written in its vector instructions. The compiler vectorises the loop
// above but not the two steps around it: it turns the eight answers into a mask lane by lane
// (about 25 instructions where one movemask does), and it reads the children's meta bytes one
// entered child at a time, a loop of unpredictable length. Here:
//   - The near and far planes of each axis are read at byte offsets the ray's signs chose
//     once (make_eight_lane_ray), so a node costs six loads and no selects: per child the
//     very operations of the loop.
//   - _mm256_max_ps(a, acc) is a > acc ? a : acc, max_onto exactly (and min likewise), so
//     NaN is ignored as before.
//   - The eight meta bytes become eight hit-mask contributions at once (meta_bits, lane by
//     lane: a variable shift per lane), the lanes not entered are zeroed by the comparison's
//     own mask, and the eight are ORed together as the loop ORs them.

// All ones in the lanes of the children the ray enters within [tmin, tmax]. `planes` is the
// first byte of the six plane arrays. `t_enter` receives each child's entry distance (the
// CPU's own traversal, cpu_traverse.h, orders the children by it).
RT_INLINE_ON_CPU inline __m256 enter_eight(const void* planes, const EightLaneRay& r,
                                           float tmin, float tmax, __m256& t_enter) {
  const auto distance = [&](int offset, __m256 origin, __m256 inverse) {
    const float* plane =
        reinterpret_cast<const float*>(static_cast<const char*>(planes) + offset);
    return _mm256_mul_ps(_mm256_sub_ps(_mm256_loadu_ps(plane), origin), inverse);
  };
  t_enter =
      _mm256_max_ps(distance(r.near_z, r.origin_z, r.inverse_z),
                    _mm256_max_ps(distance(r.near_y, r.origin_y, r.inverse_y),
                                  _mm256_max_ps(distance(r.near_x, r.origin_x, r.inverse_x),
                                                _mm256_set1_ps(tmin))));
  const __m256 infinity = _mm256_set1_ps(std::numeric_limits<float>::infinity());
  const __m256 t_exit = _mm256_mul_ps(
      _mm256_min_ps(
          distance(r.far_z, r.origin_z, r.inverse_z),
          _mm256_min_ps(distance(r.far_y, r.origin_y, r.inverse_y),
                        _mm256_min_ps(distance(r.far_x, r.origin_x, r.inverse_x), infinity))),
      _mm256_set1_ps(k_exit_widening));
  const __m256 tmax_kept = _mm256_set1_ps(tmax * ch07::k_tmax_slack);
  return _mm256_cmp_ps(t_enter, _mm256_min_ps(t_exit, tmax_kept), _CMP_LE_OQ);
}
RT_INLINE_ON_CPU inline __m256 enter_eight(const void* planes, const EightLaneRay& r,
                                           float tmin, float tmax) {
  __m256 t_enter;
  return enter_eight(planes, r, tmin, tmax, t_enter);
}

// meta_bits of the eight children, ORed over the lanes of `entered`.
RT_INLINE_ON_CPU inline unsigned
eight_meta_bits(__m256 entered, const std::uint8_t (&meta)[k_slots], __m256i octant_inverse) {
  std::uint64_t bytes;
  std::memcpy(&bytes, meta, sizeof bytes);
  const __m256i m = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(bytes)));
  const __m256i low5 = _mm256_and_si256(m, _mm256_set1_epi32(31));
  const __m256i interior_bits = _mm256_set1_epi32(0x18);
  const __m256i interior =
      _mm256_cmpeq_epi32(_mm256_and_si256(m, interior_bits), interior_bits);
  const __m256i shift = _mm256_xor_si256(low5, _mm256_and_si256(interior, octant_inverse));
  const __m256i bits = _mm256_and_si256(_mm256_sllv_epi32(_mm256_srli_epi32(m, 5), shift),
                                        _mm256_castps_si256(entered));
  __m128i x = _mm_or_si128(_mm256_castsi256_si128(bits), _mm256_extracti128_si256(bits, 1));
  x = _mm_or_si128(x, _mm_unpackhi_epi64(x, x));
  x = _mm_or_si128(x, _mm_shuffle_epi32(x, 1));
  return static_cast<unsigned>(_mm_cvtsi128_si32(x));
}
// [/listing:node_avx2]

// Both kinds of eight-wide node, whose planes lie as enter_eight reads them: the compressed
// one dequantised first.
static_assert(offsetof(WideNode<8>, lo_x) == 0 && offsetof(WideNode<8>, hi_z) == 5 * 32);
static_assert(offsetof(ChildPlanes, lo_x) == 0 && offsetof(ChildPlanes, hi_z) == 5 * 32);
RT_INLINE_ON_CPU inline unsigned node_bits_avx2(const WideNode<8>& n, const EightLaneRay& r,
                                                float tmin, float tmax) {
  return eight_meta_bits(enter_eight(&n, r, tmin, tmax), n.meta, r.octant_inverse);
}
RT_INLINE_ON_CPU inline unsigned node_bits_avx2(const CompressedNode& n, const EightLaneRay& r,
                                                float tmin, float tmax) {
  // dequantise_planes eight at a time: q to float, times the step, plus the origin (the same
  // two roundings, of which the first is exact).
  const auto plane = [](const std::uint8_t(&q)[k_slots], std::uint8_t exponent, float origin) {
    std::uint64_t bytes;
    std::memcpy(&bytes, q, sizeof bytes);
    const __m256 grid = _mm256_cvtepi32_ps(
        _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(bytes))));
    return _mm256_add_ps(_mm256_mul_ps(grid, _mm256_set1_ps(grid_step(exponent))),
                         _mm256_set1_ps(origin));
  };
  alignas(32) ChildPlanes p;
  _mm256_store_ps(p.lo_x, plane(n.q_lo_x, n.exponent[0], n.origin[0]));
  _mm256_store_ps(p.lo_y, plane(n.q_lo_y, n.exponent[1], n.origin[1]));
  _mm256_store_ps(p.lo_z, plane(n.q_lo_z, n.exponent[2], n.origin[2]));
  _mm256_store_ps(p.hi_x, plane(n.q_hi_x, n.exponent[0], n.origin[0]));
  _mm256_store_ps(p.hi_y, plane(n.q_hi_y, n.exponent[1], n.origin[1]));
  _mm256_store_ps(p.hi_z, plane(n.q_hi_z, n.exponent[2], n.origin[2]));
  return eight_meta_bits(enter_eight(&p, r, tmin, tmax), n.meta, r.octant_inverse);
}
#endif
#endif

// What one node read yields: the interior children the ray enters (bits 24..31, ordered for
// its octant) with the node's imask in bits 0..7, and the triangles of the leaves it enters.
struct NodeHits {
  unsigned children; // a node group: hit bits 24..31 | imask
  unsigned triangles;
  int child_base;
  int triangle_base;
};

template <class Node>
RT_INLINE_ON_CPU RT_HD inline NodeHits node_hits(const Node& n, unsigned bits) {
  return {(bits & 0xff000000u) | n.imask, bits & 0x00ffffffu, n.child_base, n.triangle_base};
}

// A node read with no vector instructions written out, whatever the compile flags: the GPU's,
// the CPU's where it has no AVX2 form (below), and the reference that form is tested against.
template <class Node>
RT_INLINE_ON_CPU RT_HD inline NodeHits intersect_node(const Node& n, const WideRay& r,
                                                      float tmin, float tmax) {
  unsigned bits = 0;
#if defined(__CUDA_ARCH__)
  const unsigned entered = enter_children(slabs_of(n, r), r.box, tmin, tmax);
#pragma unroll
  for (int c = 0; c < Node::k_width; ++c)
    bits |= (entered >> c) & 1u ? meta_bits(n.meta[c], r.octant_inverse) : 0u;
#else
  // the children entered only: a few of the eight, one at a time
  const unsigned entered = enter_children_cpu(n, r, tmin, tmax);
  for (unsigned left = entered; left != 0; left &= left - 1)
    bits |= meta_bits(n.meta[std::countr_zero(left)], r.octant_inverse);
#endif
  return node_hits(n, bits);
}

#if !defined(__CUDA_ARCH__) && defined(__AVX2__)
// With the ray's eight lanes, an eight-wide node is read in AVX2, a narrower one as above.
template <class Node>
RT_INLINE_ON_CPU inline NodeHits intersect_node(const Node& n, const WideRayAvx2& r, float tmin,
                                                float tmax) {
  if constexpr (Node::k_width == 8)
    return node_hits(n, node_bits_avx2(n, r.lanes, tmin, tmax));
  else
    return intersect_node(n, static_cast<const WideRay&>(r), tmin, tmax);
}
#endif

// The ray as the traversal carries it: a WideRay, with its eight lanes where the CPU code is
// compiled with AVX2 (which intersect_node above then takes).
RT_INLINE_ON_CPU RT_HD inline auto make_traversal_ray(const RayF& ray) {
  const WideRay r = make_wide_ray(ray);
#if !defined(__CUDA_ARCH__) && defined(__AVX2__)
  return WideRayAvx2{r, make_eight_lane_ray(r)};
#else
  return r;
#endif
}

RT_HD inline int highest_bit(unsigned x) {
#if defined(__CUDA_ARCH__)
  return 31 - __clz(x);
#else
  return 31 - std::countl_zero(x);
#endif
}
RT_HD inline int lowest_bit(unsigned x) {
#if defined(__CUDA_ARCH__)
  return __ffs(x) - 1;
#else
  return std::countr_zero(x);
#endif
}
RT_HD inline int bit_count(unsigned x) {
#if defined(__CUDA_ARCH__)
  return __popc(x);
#else
  return std::popcount(x);
#endif
}

// A node group on the stack: the children of one node still to visit (hit bits 24..31, the
// highest first) and where they are (child_base, and the node's imask in bits 0..7).
struct NodeGroup {
  int base;
  unsigned hits;
};
inline constexpr unsigned k_child_bits = 0xff000000u;

// The triangle test of one ray: chapter 04's watertight test. On the CPU its per-ray part (the
// permutation and the shear, three divisions) is made once per ray instead of once per
// triangle, and `Axes` may fix the permutation when the code is compiled (trace_wide_cpu does,
// wide_trace.cpp); the GPU keeps chapter 04's one call per triangle, the form its tables
// measure.
#if defined(__CUDA_ARCH__)
struct WatertightTest {
  __device__ explicit WatertightTest(const RayF&) {}
  __device__ ch04::TriangleHitF operator()(const RayF& ray, const TriangleF& triangle) const {
    return ch04::intersect_watertight(ray, triangle);
  }
};
#else
template <class Axes> struct FramedWatertightTest {
  ch04::WatertightRay<float> frame;
  explicit FramedWatertightTest(const RayF& ray) : frame(ch04::watertight_ray(ray)) {}
  explicit FramedWatertightTest(const ch04::WatertightRay<float>& f) : frame(f) {}
  RT_INLINE_ON_CPU ch04::TriangleHitF operator()(const RayF& ray, const TriangleF& triangle) {
    frame.ray.tmax = ray.tmax; // the nearest hit so far
    return ch04::intersect_watertight(frame, triangle, Axes{});
  }
};
using WatertightTest = FramedWatertightTest<ch04::AxesOfFrame>;
#endif

// [listing:test_triangles]
// The triangles of the leaves a node read entered, `bits` counted from `base`, lowest bit
// first: a hit nearer than ray.tmax becomes `hit` and the new ray.tmax, so of two triangles
// at the same distance the first tested is kept. True when an any-hit query is answered.
template <Query kQuery, class Tree, class C, class Test>
RT_INLINE_ON_CPU RT_HD inline bool test_triangles(const Tree& tree, int base, unsigned bits,
                                                  RayF& ray, TraceHit& hit, C& counters,
                                                  Test& intersect) {
  for (unsigned left = bits; left != 0; left &= left - 1) {
    const int k = base + lowest_bit(left);
    counters.triangle();
    const ch04::TriangleHitF t = intersect(ray, tree.triangle(k));
    if (!t.hit) continue;
    hit = {t.t, tree.triangle_id(k), t.u, t.v};
    ray.tmax = t.t;
    if (kQuery == Query::any) return true;
  }
  return false;
}
// [/listing:test_triangles]

#if !defined(__CUDA_ARCH__)
// Where triangles k .. k + 7 of a tree with columns lie, as the eight-at-once test reads them
// (intersect_eight, below): one long column per coordinate. (The CPU's own tree keeps them in
// blocks of eight: cpu_tree.h.)
struct EightColumns {
  const float* first; // coordinate c of the eight from first + c * stride
  int stride;
};
template <class Tree>
RT_INLINE_ON_CPU inline EightColumns eight_columns(const Tree& tree, int k) {
  return {tree.columns + k, tree.column_stride};
}
#endif

#if !defined(__CUDA_ARCH__) && defined(__AVX2__) && defined(__FMA__)
// [listing:triangles_avx2]
// On a CPU with AVX2 and FMA, for the traversal with the axes fixed (trace_wide_cpu), eight
// triangles at a time from the tree's columns: chapter 04's watertight test lane by lane,
// every value computed by the same operations (its fused_multiply_adds are FMA instructions,
// the rest rounded singly as the scalar code is) and every decision the same, so each lane
// gives the scalar test's answer bit for bit. Which lane wins is the scalar loop's rule: the
// nearest t, and of equal ones the lowest bit. One load per coordinate for eight triangles
// replaces eight rounds of nine scalar loads and the data-dependent branches of each test.
struct EightTriangleHits {
  __m256 t, v_edge, w_edge, inverse_det;
  unsigned hit; // lanes whose triangle is hit within (tmin, tmax)
};

// Coordinate c (v0.x v0.y v0.z v1.x ... v2.z) of the eight triangles lies at first + c *
// stride, eight consecutive floats.
template <int X, int Y, int Z>
RT_INLINE_ON_CPU inline EightTriangleHits
intersect_eight(const float* first, int stride, const ch04::WatertightRay<float>& frame,
                const RayF& ray) {
  const __m256 sx = _mm256_set1_ps(frame.shear_x), sy = _mm256_set1_ps(frame.shear_y),
               sz = _mm256_set1_ps(frame.shear_z);
  const __m256 ox = _mm256_set1_ps(ray.origin[X]), oy = _mm256_set1_ps(ray.origin[Y]),
               oz = _mm256_set1_ps(ray.origin[Z]);
  struct Moved {
    __m256 x, y, z; // sheared x and y, and z relative to the origin
  };
  const auto move = [&](int vertex) {
    const auto column = [&](int axis) {
      return _mm256_loadu_ps(first + (3 * vertex + axis) * stride);
    };
    const __m256 dz = _mm256_sub_ps(column(Z), oz);
    return Moved{_mm256_fnmadd_ps(sx, dz, _mm256_sub_ps(column(X), ox)),
                 _mm256_fnmadd_ps(sy, dz, _mm256_sub_ps(column(Y), oy)), dz};
  };
  const Moved a = move(0), b = move(1), c = move(2);
  // difference_of_products(p, q, r, s): fma(p, q, -r*s) + fma(-r, s, r*s)
  const auto dop = [](__m256 p, __m256 q, __m256 r, __m256 s) {
    const __m256 rs = _mm256_mul_ps(r, s);
    return _mm256_add_ps(_mm256_fmsub_ps(p, q, rs), _mm256_fnmadd_ps(r, s, rs));
  };
  const __m256 u_edge = dop(c.x, b.y, c.y, b.x);
  const __m256 v_edge = dop(a.x, c.y, a.y, c.x);
  const __m256 w_edge = dop(b.x, a.y, b.y, a.x);
  // Chapter 04's inside test, all signs the same (zeros allowed), then det != 0, decided
  // as one: the smallest edge >= 0 or the largest <= 0, and det < 0 or det > 0. A NaN edge
  // fails chapter 04's comparisons and here makes det NaN, which fails both of its.
  const __m256 lowest = _mm256_min_ps(w_edge, _mm256_min_ps(v_edge, u_edge));
  const __m256 highest = _mm256_max_ps(w_edge, _mm256_max_ps(v_edge, u_edge));
  const __m256 det = _mm256_add_ps(_mm256_add_ps(u_edge, v_edge), w_edge);
  const __m256 zero = _mm256_setzero_ps();
  const __m256 inside = _mm256_or_ps(_mm256_cmp_ps(lowest, zero, _CMP_GE_OQ),
                                     _mm256_cmp_ps(highest, zero, _CMP_LE_OQ));
  const __m256 det_nonzero =
      _mm256_or_ps(_mm256_cmp_ps(det, zero, _CMP_LT_OQ), _mm256_cmp_ps(det, zero, _CMP_GT_OQ));
  const __m256 t_times_det =
      _mm256_fmadd_ps(u_edge, _mm256_mul_ps(sz, a.z),
                      _mm256_fmadd_ps(v_edge, _mm256_mul_ps(sz, b.z),
                                      _mm256_mul_ps(w_edge, _mm256_mul_ps(sz, c.z))));
  const __m256 inverse_det = _mm256_div_ps(_mm256_set1_ps(1.0f), det);
  const __m256 t = _mm256_mul_ps(t_times_det, inverse_det);
  const __m256 in_range = _mm256_and_ps(_mm256_cmp_ps(t, _mm256_set1_ps(ray.tmin), _CMP_GT_OQ),
                                        _mm256_cmp_ps(t, _mm256_set1_ps(ray.tmax), _CMP_LT_OQ));
  const __m256 hit = _mm256_and_ps(_mm256_and_ps(inside, det_nonzero), in_range);
  return {t, v_edge, w_edge, inverse_det, unsigned(_mm256_movemask_ps(hit))};
}

// test_triangles' loop over the same bits, eight triangles per step from the tree's columns
// (which it must have), for a ray whose frame has the axes X, Y, Z.
template <Query kQuery, class Tree, int X, int Y, int Z>
RT_INLINE_ON_CPU inline bool
test_triangles_avx2(const Tree& tree, int base, unsigned bits, RayF& ray, TraceHit& hit,
                    const ch04::WatertightRay<float>& frame, ch04::FixedAxes<X, Y, Z>) {
  for (unsigned left = bits; left != 0;) {
    const int first = lowest_bit(left) & ~7; // triangles first .. first + 7
    const unsigned lanes = (left >> first) & 0xffu;
    left &= ~(0xffu << first);
    const EightColumns columns = eight_columns(tree, base + first);
    const EightTriangleHits e =
        intersect_eight<X, Y, Z>(columns.first, columns.stride, frame, ray);
    const unsigned found = e.hit & lanes;
    if (found == 0) continue;
    alignas(32) float t[8];
    _mm256_store_ps(t, e.t);
    int lane = lowest_bit(found);
    if (kQuery == Query::closest) // the nearest; of equal ones, the lowest lane
      for (unsigned rest = found & (found - 1); rest != 0; rest &= rest - 1)
        if (t[lowest_bit(rest)] < t[lane]) lane = lowest_bit(rest);
    alignas(32) float v_edge[8], w_edge[8], inverse_det[8];
    _mm256_store_ps(v_edge, e.v_edge);
    _mm256_store_ps(w_edge, e.w_edge);
    _mm256_store_ps(inverse_det, e.inverse_det);
    const int k = base + first + lane;
    hit = {t[lane], tree.triangle_id(k), v_edge[lane] * inverse_det[lane],
           w_edge[lane] * inverse_det[lane]};
    ray.tmax = t[lane];
    if (kQuery == Query::any) return true;
  }
  return false;
}
// [/listing:triangles_avx2]
#endif

// The triangle test a node read's triangles get in trace_wide: test_triangles, the scalar
// loop; or, on a CPU with AVX2 and FMA, in a traversal with the axes fixed and no counters
// through a tree with columns, test_triangles_avx2.
template <Query kQuery, class Tree, class C, class Test>
RT_INLINE_ON_CPU RT_HD inline bool test_node_triangles(const Tree& tree, int base,
                                                       unsigned bits, RayF& ray, TraceHit& hit,
                                                       C& counters, Test& intersect) {
  return test_triangles<kQuery>(tree, base, bits, ray, hit, counters, intersect);
}
#if !defined(__CUDA_ARCH__) && defined(__AVX2__) && defined(__FMA__)
template <Query kQuery, class Tree, int X, int Y, int Z>
RT_INLINE_ON_CPU inline bool
test_node_triangles(const Tree& tree, int base, unsigned bits, RayF& ray, TraceHit& hit,
                    ch07::NoCounters& counters,
                    FramedWatertightTest<ch04::FixedAxes<X, Y, Z>>& test) {
  if (tree.columns == nullptr)
    return test_triangles<kQuery>(tree, base, bits, ray, hit, counters, test);
  return test_triangles_avx2<kQuery>(tree, base, bits, ray, hit, test.frame,
                                     ch04::FixedAxes<X, Y, Z>{});
}
#endif

// [listing:local_stack]
// Where trace_wide keeps its stack is a policy: entry `entry` stored and loaded. This one, the
// default and the only one the CPU uses, is the thread's own array of k_wide_stack_size
// entries; the GPU keeps it in local memory (cached in L1), since it is indexed at run time.
struct LocalStack {
  NodeGroup entries[k_wide_stack_size];
  RT_HD void store(int entry, NodeGroup group) { entries[entry] = group; }
  RT_HD NodeGroup load(int entry) const { return entries[entry]; }
};
// [/listing:local_stack]

// [listing:wide_traverse]
// The closest (or any) hit of `ray` among the tree's triangles, the same as chapter 07's
// trace_bvh up to which of two triangles at exactly the same distance is kept.
//
// The current node group's highest bit is the next child: its slot gives its node number
// (child_base + the interior children in slots below it), and what is left of the group is
// pushed before the child is read. The child's interior hits become the new group; its leaf
// triangles are tested at once, lowest bit first. An empty group pops the next one. The root
// starts as the only interior child, in slot 0, of a group based at node 0. Groups carry no
// distance: one popped after a nearer hit is tested again with the shorter ray, and its
// children's boxes reject what now lies beyond tmax. `Stack` says where the stack lives.
// `intersect` is the triangle test (WatertightTest or, on the CPU, one with fixed axes).
// `root` is the node the walk starts from: 0, the tree's root, or (chapter 13) the root of a
// subtree, whose triangles alone are then searched.
template <Query kQuery, class Stack = LocalStack, class Tree, class C, class Test>
RT_HD TraceHit trace_wide(const Tree& tree, RayF ray, C&& counters, Test intersect,
                          int root = 0) {
  TraceHit hit;
  if (tree.node_count == 0 || !ch07::traceable(ray)) return hit;
  const auto r = make_traversal_ray(ray);
  Stack stack;
  int stack_size = 0;
  NodeGroup group{root, (1u << (24 + r.octant_inverse)) | 1u};
  for (;;) {
    if ((group.hits & k_child_bits) == 0) {
      if (stack_size == 0) return hit;
      group = stack.load(--stack_size);
    }
    const int bit = highest_bit(group.hits);
    group.hits &= ~(1u << bit);
    const unsigned slot = unsigned(bit - 24) ^ r.octant_inverse;
    const int node = group.base + bit_count(group.hits & ((1u << slot) - 1u) & 0xffu);
    if (group.hits & k_child_bits) {
      stack.store(stack_size++, group);
      counters.stack(stack_size);
    }
    counters.node();
    const NodeHits h = intersect_node(tree.node(node), r, ray.tmin, ray.tmax);
    group = {h.child_base, h.children};
    if (test_node_triangles<kQuery>(tree, h.triangle_base, h.triangles, ray, hit, counters,
                                    intersect))
      return hit; // an any-hit query is answered
  }
}
// [/listing:wide_traverse]

template <Query kQuery, class Stack = LocalStack, class Tree, class C = ch07::NoCounters>
RT_HD TraceHit trace_wide(const Tree& tree, RayF ray, C&& counters = C{}, int root = 0) {
  return trace_wide<kQuery, Stack>(tree, ray, counters, WatertightTest(ray), root);
}

} // namespace rt::ch09
