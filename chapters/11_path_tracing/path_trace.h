// Chapter 11: a unidirectional path tracer for Lambertian scenes, one path vertex at a time.
// shade_vertex is the whole physics: it adds what the path sees at a hit (emission, weighted
// by multiple importance sampling), prepares the shadow rays of next-event estimation, and
// either ends the path or bounces it. The megakernel loops over it per pixel; the wavefront
// variant (wavefront.h) runs the same function as one stage of several. A kernel that runs it
// is compiled with -fmad=false and defines RT_NO_CONTRACTION (chapter 07's cosine_sampling.h),
// so the GPU and the CPU trace the same paths bit for bit.
#pragma once

#include <limits>

#include <vector_types.h>

#include "collapse.h"
#include "path_random.h"
#include "path_sampling.h"
#include "path_scene.h"
#include "ray.h"
#include "rt/atomic.h"
#include "samplers.h"
#include "spawn.h"
#include "wide_traverse.h"

namespace rt::ch11 {

using ch03::RayF;
using ch07::Query;
using ch07::TraceHit;

// The features a kernel is compiled for (chapter 06's Specialised and AllFeatures carry them).
enum PathFeature : unsigned {
  k_emitters = 1u << 0, // emitting triangles: their emission, next-event estimation, MIS
  k_sky = 1u << 1,      // a constant sky for rays that leave the scene
  k_sun = 1u << 2,      // a directional light, sampled by shadow rays
};
inline constexpr unsigned k_all_path_features = k_emitters | k_sky | k_sun;

// How direct light from the emitting triangles is found.
enum class Strategy : int {
  bsdf,  // only by bounced rays that happen to hit an emitter
  light, // only by next-event estimation (shadow rays to sampled points of the emitters)
  mis,   // both, weighted by the power heuristic
};

// Russian roulette starts at this vertex: the first bounces are always traced, where paths
// carry the most light and ending them would add the most variance.
inline constexpr int k_roulette_from_vertex = 3;
// A path survives roulette with the probability of its throughput's largest channel, capped
// here: one between white walls, whose throughput stays near 1, still ends after about 20
// more surfaces.
inline constexpr float k_roulette_max_survival = 0.95f;

// The tree paths are traced through: chapter 09's 4-wide tree with 40-byte triangles, the one
// that met all of that chapter's GPU targets (speed and at most 64 bytes per triangle).
using PathTree = ch09::Wide4PackedBvh;
inline PathTree build_path_tree(const ch04::Mesh& mesh) {
  return ch09::pack_wide<4, ch09::PackedTriangles>(
      ch09::build_wide_layout(mesh, 4, ch09::Collapse::sah));
}

struct PathState;

// The scene as the kernels read it (device pointers on the GPU, host pointers on the CPU).
struct PathSceneView {
  using Path = PathState; // what a path carries from vertex to vertex (path_kernels.cuh)
  PathTree::View tree;    // chapter 09's wide tree
  ch04::MeshView mesh;    // positions, by the mesh's triangle numbers
  const int* material;    // per triangle
  const PathMaterial* materials;
  const int* light_triangles; // LightTable::triangles
  const float* light_cdf;     // LightTable::cdf
  int light_count;
  float light_power; // LightTable::power
  Environment environment;
  Sampler sampler; // where the paths' numbers come from (samplers.h): set for each pass
};

// One path in flight: 72 bytes the wavefront keeps per path between its stages.
struct PathState {
  RayF ray;         // the next ray to trace (unit direction)
  Vec3f throughput; // the product of f cos / pdf (and 1 / roulette survival) so far
  Vec3f radiance;   // what the path has gathered
  float bsdf_pdf;   // density of ray.direction at the last vertex (0: the camera ray)
  unsigned pixel;   // y * width + x
  unsigned sample;  // the sample index within the pixel
  int vertex;       // surfaces met so far
};
static_assert(sizeof(PathState) == 72);

// The shadow rays one vertex asks for: the sun's and an emitter's. Each adds its
// contribution to the path's radiance if nothing blocks it.
struct ShadowRays { // 92 bytes
  RayF ray[2];
  Vec3f contribution[2];
  int count = 0;
};
static_assert(sizeof(ShadowRays) == 92);

// The path's two numbers of a pad at its current vertex (dimensions first and first + 1,
// first even), from the scene's sampler.
RT_HD inline Vec2f number_pair(const Sampler& sampler, const PathState& path, unsigned first) {
  return sample_pair(sampler, path.pixel, path.sample, unsigned(path.vertex), first);
}

// [listing:vertex_numbers]
// The numbers a surface vertex draws, pad by pad (samplers.h): the bounce's pair, Russian
// roulette's and the light pick's, the point on the light, and a spare pair a later chapter
// uses; `pads` says which (a mask of k_pad_* bits), so that a vertex with no next-event
// estimation and no roulette draws only its bounce. They are drawn together, with one choice of
// sampler for the vertex rather than one for each number: the short samplers (independent,
// sobol) in a loop the compiler unrolls, the long ones (stratified, zsobol) in a loop the GPU's
// compiler is told to keep rolled, so that their code appears once in the kernel rather than
// once for each place a number is used; with four samplers behind a switch at every use, the
// copies made the kernel large enough to slow the GPU. The numbers are the same as one at a
// time, whatever order they are drawn in.
struct VertexNumbers {
  Vec2f bsdf;       // k_bsdf_u, k_bsdf_v
  float roulette;   // k_roulette
  float light_pick; // k_light_pick
  Vec2f light;      // k_light_u, k_light_v
  Vec2f spare;      // dimensions 6 and 7
};
enum PadMask : unsigned {
  k_pad_bsdf = 1u << 0,     // VertexNumbers::bsdf
  k_pad_roulette = 1u << 1, // roulette and light_pick (one pad)
  k_pad_light = 1u << 2,    // light
  k_pad_spare = 1u << 3,    // spare
};
RT_HD inline void put_pad(VertexNumbers& u, unsigned pad, Vec2f p) {
  if (pad == 0) u.bsdf = p;
  if (pad == 1) u.roulette = p.x, u.light_pick = p.y;
  if (pad == 2) u.light = p;
  if (pad == 3) u.spare = p;
}
RT_HD inline VertexNumbers vertex_numbers(const Sampler& sampler, const PathState& path,
                                          unsigned pads) {
  VertexNumbers u{};
  const unsigned vertex = unsigned(path.vertex), first_pad = vertex * k_pads_per_vertex;
  if (sampler.kind == SamplerKind::independent) {
    RT_UNROLL
    for (unsigned pad = 0; pad < 4; ++pad)
      if ((pads >> pad) & 1u)
        put_pad(u, pad,
                {sample_number(path.pixel, path.sample, vertex, 2 * pad),
                 sample_number(path.pixel, path.sample, vertex, 2 * pad + 1)});
  } else if (sampler.kind == SamplerKind::sobol) {
    RT_UNROLL
    for (unsigned pad = 0; pad < 4; ++pad)
      if ((pads >> pad) & 1u)
        put_pad(u, pad, sobol_pair(path.pixel, path.sample, first_pad + pad));
  } else {
#if RT_ON_DEVICE
#pragma unroll 1
#endif
    for (unsigned pad = 0; pad < 4; ++pad)
      if ((pads >> pad) & 1u) put_pad(u, pad, number_pair(sampler, path, 2 * pad));
  }
  return u;
}
// [/listing:vertex_numbers]

// The camera ray through the point (jx, jy) away from the centre of pixel (x, y), jx and jy
// in [-0.5, 0.5): chapter 03's camera formula with the pixel centre moved.
RT_HD inline RayF camera_ray_jittered(const ch03::Camera<float>& camera, int x, int y, float jx,
                                      float jy) {
  const auto& c = camera.pinhole;
  const float sx =
      (2.0f * (float(x) + 0.5f + jx) / float(c.width) - 1.0f) * c.tan_half_vfov * c.aspect;
  const float sy = (1.0f - 2.0f * (float(y) + 0.5f + jy) / float(c.height)) * c.tan_half_vfov;
  if (camera.kind == ch03::CameraKind::pinhole) {
    const Vec3f d = c.basis.right * sx + c.basis.up * sy + c.basis.forward;
    return {c.eye, normalize(d)};
  }
  const auto& o = camera.orthographic;
  const float scale = o.half_height / c.tan_half_vfov;
  return {o.eye + (o.basis.right * sx + o.basis.up * sy) * scale, o.basis.forward};
}

// The camera ray through a uniform random point of pixel (x, y) (vertex 0's two numbers, from
// `sampler`).
RT_HD inline PathState start_path(const ch03::Camera<float>& camera, int x, int y,
                                  unsigned sample, const Sampler& sampler = {}) {
  PathState path{};
  path.pixel = unsigned(y * camera.pinhole.width + x);
  path.sample = sample;
  const Vec2f jitter = number_pair(sampler, path, 0);
  path.ray = camera_ray_jittered(camera, x, y, jitter.x - 0.5f, jitter.y - 0.5f);
  path.throughput = {1.0f, 1.0f, 1.0f};
  return path;
}
// The same, named by the scene it will be traced in: the kernels (path_kernels.cuh) start
// every scene's paths this way, and a later chapter's scene starts its own.
RT_HD inline PathState start_path(const PathSceneView& s, const ch03::Camera<float>& camera,
                                  int x, int y, unsigned sample) {
  return start_path(camera, x, y, sample, s.sampler);
}

// The emitting triangle for a number in [0, 1): the first whose cumulative probability
// exceeds it (binary search).
RT_HD inline int pick_light(const PathSceneView& s, float u) {
  int lo = 0, hi = s.light_count - 1;
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (s.light_cdf[mid] > u)
      hi = mid;
    else
      lo = mid + 1;
  }
  return s.light_triangles[lo];
}

// A point on an emitter, drawn by next-event estimation.
struct LightPoint {
  int triangle;            // the mesh's triangle number
  ch04::TriangleF corners; // its corners
  Vec3f point;             // uniform on it
};

// The light table's emitter for u_pick, then a uniform point on it for (u, v).
RT_HD inline LightPoint sample_light_point(const PathSceneView& s, float u_pick, float u,
                                           float v) {
  const int light = pick_light(s, u_pick);
  const ch04::TriangleF t = s.mesh.triangle(light);
  return {light, t, point_on_triangle(t.v0, t.v1, t.v2, u, v)};
}

// The density per unit area of sample_light_point's points on an emitter of emission
// `emission`: its triangle is picked with probability area * luminance / power and the point
// is uniform on its area, so the area cancels.
RT_HD inline float light_area_density(const PathSceneView& s, Vec3f emission) {
  return luminance(emission) / s.light_power;
}

// The unit normal of a triangle's front face, the side from which its corners run
// counter-clockwise; `fallback` for a sliver whose float cross product has no direction.
RT_HD inline Vec3f front_normal(const ch04::TriangleF& t, Vec3f fallback) {
  const Vec3f n = cross(t.v1 - t.v0, t.v2 - t.v0);
  const float len = length(n);
  return len > 0.0f ? n / len : fallback;
}

// [listing:spawn_origin]
// Chapter 03's offset (spawn.h), scaled by the largest coordinate of the point *and of its
// triangle*. Chapter 03 warned that its offset assumes the point is as accurate as its own
// coordinates; a hit near the origin on a floor that reaches out to +-4 is only as accurate
// as the floor's corners, and a path tracer finds such points all the time: every bounce from
// the middle of a large floor. Scaled by the point alone, shadow rays from there find the
// floor itself, and the disc test (tests/11_path_tracing) comes out 3% dark.
RT_HD inline Vec3f spawn_origin(Vec3f p, Vec3f n, const ch04::TriangleF& t) {
  const float largest = max_of(max_component(elementwise_abs(p)),
                               max_of(max_component(elementwise_abs(t.v0)),
                                      max_of(max_component(elementwise_abs(t.v1)),
                                             max_component(elementwise_abs(t.v2)))));
  return ch03::offset_ray_origin(p, n, largest);
}
// [/listing:spawn_origin]

// The face normal on the side `side` points to: surfaces reflect on both sides.
RT_HD inline Vec3f facing_normal(const ch04::TriangleF& t, Vec3f side) {
  const Vec3f unit = front_normal(t, side);
  return dot(unit, side) < 0.0f ? -unit : unit;
}

// [listing:next_event]
// Next-event estimation at p (normal n, albedo a): a point q on an emitter, picked by the
// light table, and the shadow ray from p to it. Its contribution is the estimator
// f cos_p Le / pdf, with f = a / pi and pdf the density of q's direction per solid angle,
// (lum(Le) / power) * d^2 / cos_q; under MIS it is weighted against the density with which
// the cosine-weighted bounce would have found the same direction.
RT_HD inline void sample_emitter(const PathSceneView& s, const PathState& path,
                                 const VertexNumbers& u, Vec3f origin, Vec3f n, Vec3f albedo,
                                 Strategy strategy, ShadowRays& shadows) {
  const LightPoint light = sample_light_point(s, u.light_pick, u.light.x, u.light.y);
  const ch04::TriangleF& t = light.corners;
  const Vec3f q = light.point;
  const Vec3f n_light = front_normal(t, origin - q); // emitters emit from their front
  const Vec3f target = spawn_origin(q, n_light, t);  // off the emitter, in front
  const Vec3f to_light = target - origin;
  const float distance_squared = length_squared(to_light);
  const float distance = square_root(distance_squared);
  const float cos_p = dot(n, to_light) / distance;
  const float cos_q = dot(n_light, -to_light) / distance;
  if (!(cos_p > 0.0f && cos_q > 0.0f)) return; // behind the surface, or seen edge-on
  const Vec3f emission = s.materials[s.material[light.triangle]].emission;
  const float pdf_light = light_area_density(s, emission) * distance_squared / cos_q;
  const float weight =
      strategy == Strategy::mis ? power_heuristic(pdf_light, cosine_density(cos_p)) : 1.0f;
  const int k = shadows.count++;
  shadows.ray[k] = {origin, to_light, 0.0f, 1.0f}; // the emitter sits at t = 1
  shadows.contribution[k] =
      path.throughput * albedo * emission * (weight * cos_p / (k_pi * pdf_light));
}
// [/listing:next_event]

// [listing:shade_vertex]
// The weight of an emitter that the path's ray found at distance t, at cosine cos_q with its
// normal, emitting `emission` (the factor the light table weighs it by): 1 for the camera ray
// (bsdf_pdf 0), 0 when only shadow rays may find lights, and under MIS the power heuristic
// against the density with which next-event estimation would have picked the same point.
RT_HD inline float emitter_hit_weight(const PathSceneView& s, const PathState& path,
                                      Strategy strategy, Vec3f emission, float cos_q, float t) {
  if (!(path.bsdf_pdf > 0.0f)) return 1.0f;
  if (strategy == Strategy::light) return 0.0f;
  if (strategy == Strategy::bsdf) return 1.0f; // only bounces find lights
  const float pdf_light = light_area_density(s, emission) * t * t / absolute(cos_q);
  return power_heuristic(path.bsdf_pdf, pdf_light);
}

// Russian roulette after the bounce has weighted the throughput: false ends the path. From
// k_roulette_from_vertex on, the path survives with the probability of its throughput's
// largest channel times `scale` (1 here; a later chapter takes refraction's radiance scaling
// out this way), capped, and carries 1 / survival; before, only a black throughput ends it.
// `u` is the vertex's roulette number (VertexNumbers).
RT_HD inline bool survives_roulette(PathState& path, float u, float scale = 1.0f) {
  if (path.vertex >= k_roulette_from_vertex) {
    const float survive =
        min_of(max_component(path.throughput) * scale, k_roulette_max_survival);
    if (!(u < survive)) return false; // also ends NaN throughputs
    path.throughput = path.throughput / survive;
    return true;
  }
  return max_component(path.throughput) > 0.0f; // a black surface: nothing more comes back
}

// One vertex of a path: `hit` is what path.ray found. Adds what the path sees there, fills
// `shadows` with the next-event rays, and bounces: false when the path ends.
template <class F>
RT_HD bool shade_vertex(const PathSceneView& s, F features, Strategy strategy, PathState& path,
                        const TraceHit& hit, ShadowRays& shadows) {
  const Vec3f d = path.ray.direction;
  if (hit.triangle < 0) { // the ray left the scene
    if constexpr (F::compiled(k_sky))
      if (features.on(k_sky)) path.radiance += path.throughput * s.environment.sky;
    return false;
  }
  ++path.vertex;
  const ch04::TriangleF triangle = s.mesh.triangle(hit.triangle);
  const Vec3f n = facing_normal(triangle, -d); // reflects on both sides
  const Vec3f p = path.ray.origin + d * hit.t;
  const PathMaterial m = s.materials[s.material[hit.triangle]];
  if constexpr (F::compiled(k_emitters)) {
    const bool front = dot(front_normal(triangle, -d), d) < 0.0f; // emits from the front only
    if (features.on(k_emitters) && front && max_component(m.emission) > 0.0f)
      path.radiance += path.throughput * m.emission *
                       emitter_hit_weight(s, path, strategy, m.emission, dot(n, d), hit.t);
  }
  const Vec3f origin = spawn_origin(p, n, triangle);
  bool next_event = false; // a shadow ray to a point on an emitter
  if constexpr (F::compiled(k_emitters))
    next_event = features.on(k_emitters) && strategy != Strategy::bsdf && s.light_count > 0;
  const bool roulette = path.vertex >= k_roulette_from_vertex;
  const VertexNumbers u =
      vertex_numbers(s.sampler, path,
                     k_pad_bsdf | (next_event || roulette ? k_pad_roulette : 0u) |
                         (next_event ? k_pad_light : 0u));
  if constexpr (F::compiled(k_sun)) {
    const Environment& e = s.environment;
    const float cosine = dot(n, e.sun_direction);
    if (features.on(k_sun) && cosine > 0.0f) {
      const int k = shadows.count++;
      shadows.ray[k] = {origin, e.sun_direction};
      shadows.contribution[k] = path.throughput * m.albedo * e.sun_irradiance * (cosine / k_pi);
    }
  }
  if constexpr (F::compiled(k_emitters))
    if (next_event) sample_emitter(s, path, u, origin, n, m.albedo, strategy, shadows);
  // The bounce: cosine-weighted, so the throughput is multiplied by the albedo alone.
  const DirectionSample bounce = sample_cosine(n, u.bsdf.x, u.bsdf.y);
  path.throughput = path.throughput * m.albedo;
  if (!survives_roulette(path, u.roulette)) return false;
  path.ray = {origin, bounce.direction};
  path.bsdf_pdf = bounce.pdf;
  return true;
}
// [/listing:shade_vertex]

// [listing:megakernel]
// One step of a path in the megakernel: trace, shade, trace the shadow rays. False when the
// path ends. S is the scene's view (this chapter's PathSceneView, or a later chapter's, whose
// own shade_vertex overload C++ finds by the view's type).
template <class S, class F>
RT_HD bool extend_path(const S& s, F features, Strategy strategy, typename S::Path& path) {
  const TraceHit hit = ch09::trace_wide<Query::closest>(s.tree, path.ray);
  ShadowRays shadows;
  const bool goes_on = shade_vertex(s, features, strategy, path, hit, shadows);
  for (int k = 0; k < shadows.count; ++k)
    if (ch09::trace_wide<Query::any>(s.tree, shadows.ray[k]).triangle < 0)
      path.radiance += shadows.contribution[k];
  return goes_on;
}

// The megakernel's path: steps until it ends.
template <class S, class F>
RT_HD Vec3f trace_path(const S& s, F features, Strategy strategy,
                       const ch03::Camera<float>& camera, int x, int y, unsigned sample) {
  typename S::Path path = start_path(s, camera, x, y, sample);
  while (extend_path(s, features, strategy, path)) {
  }
  return path.radiance;
}
// [/listing:megakernel]

// Adds one sample to a pixel's running sum (x, y, z: radiance; w: samples), unless it is not
// finite: then it is dropped and counted. Both variants add samples in this one place, in
// sample order, so their sums round alike.
RT_HD inline void add_sample(float4& sum, Vec3f radiance, unsigned* non_finite) {
  const float total = radiance.x + radiance.y + radiance.z;
  if (!(total - total == 0.0f)) { // NaN or infinity in any channel
    atomic_increment(non_finite);
    return;
  }
  sum = {sum.x + radiance.x, sum.y + radiance.y, sum.z + radiance.z, sum.w + 1.0f};
}

} // namespace rt::ch11
