// Chapter 12: chapter 11's path tracer with materials. The scene's view is chapter 11's with
// chapter 12's materials, texture coordinates, textures and energy-compensation tables beside
// it; a path carries a ray cone besides chapter 11's state. shade_vertex is chapter 11's
// vertex with a BSDF (bsdf.h) where chapter 11 had an albedo: next-event estimation evaluates
// the BSDF towards the light and weighs it against the BSDF's own density; the bounce is the
// BSDF's sample. Chapter 11's kernels (path_kernels.cuh, wavefront_stages.cuh) run it
// unchanged: they find this shade_vertex and start_path by the view's type.
#pragma once

#include "bsdf.h"
#include "energy_compensation.h"
#include "material.h"
#include "path_trace.h"
#include "ray_cone.h"
#include "textures.h"

namespace rt::ch12 {

using ch11::PathState;
using ch11::ShadowRays;
using ch11::Strategy;
using ch11::TraceHit;

// The features of chapter 12's kernels: chapter 11's lights, and what the materials need.
enum MaterialFeature : unsigned {
  k_textures = 1u << 3, // texture lookups (with ray cones for their level of detail)
  k_specular = 1u << 4, // any material other than Lambertian: the BSDFs of bsdf.h
};
inline constexpr unsigned k_all_material_features =
    ch11::k_all_path_features | k_textures | k_specular;

// The dimension of a vertex that picks one of a BSDF's lobes (one of chapter 11's two spare).
inline constexpr unsigned k_lobe_pick = 6;

// A path of chapter 12: chapter 11's state, the footprint of its ray (ray_cone.h), and the
// product of the (eta_t / eta_i)^2 its refractions divided its throughput by.
struct MaterialPath : PathState {
  RayCone cone;
  float eta_scale; // 1 in the air; 2.25 inside glass of index 1.5 entered from the air
};

// [listing:material_view]
struct MaterialSceneView : ch11::PathSceneView { // the tree, mesh, light table, sky and sun
  using Path = MaterialPath;
  const Material* surfaces; // chapter 12's materials, by chapter 11's material numbers
  const Vec2f* uv;          // three per triangle (its corners'), or null
  TextureTable textures;    // the images the materials name
  CompensationView compensation;
  float pixel_spread; // the camera ray cone's spread angle (ray_cone.h)
};
// [/listing:material_view]

RT_HD inline MaterialPath start_path(const MaterialSceneView& s,
                                     const ch03::Camera<float>& camera, int x, int y,
                                     unsigned sample) {
  MaterialPath path;
  static_cast<PathState&>(path) = ch11::start_path(camera, x, y, sample, s.sampler);
  path.cone = {0.0f, s.pixel_spread}; // a point at the eye (ray_cone.h)
  path.eta_scale = 1.0f;
  return path;
}

// The barycentric coordinates (of v1 and v2) of the point p of triangle t: the hit's, found
// again from the point, whatever order the tree stores the corners in.
RT_HD inline Vec2f barycentric(const ch04::TriangleF& t, Vec3f p) {
  const Vec3f e1 = t.v1 - t.v0, e2 = t.v2 - t.v0, q = p - t.v0;
  const float d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
  const float q1 = dot(q, e1), q2 = dot(q, e2);
  const float det = d11 * d22 - d12 * d12;
  if (!(det > 0.0f)) return {1.0f / 3.0f, 1.0f / 3.0f};
  const float b1 = clamp_to((d22 * q1 - d12 * q2) / det, 0.0f, 1.0f);
  const float b2 = clamp_to((d11 * q2 - d12 * q1) / det, 0.0f, 1.0f - b1);
  return {b1, b2};
}

// What the surface is at one hit: its BSDF with the textures applied, and its emission.
struct SurfaceAt {
  Bsdf bsdf;
  Vec3f emission;
};

// [listing:surface_at]
// The textures' level of detail comes from the ray's cone where it meets the triangle, at an
// angle whose cosine is cos_incidence, each texture's from its own size (ray_cone.h).
template <class F>
RT_HD SurfaceAt surface_at(const MaterialSceneView& s, F features, const Material& m,
                           int triangle, const ch04::TriangleF& corners, Vec3f p, RayCone cone,
                           float cos_incidence) {
  Vec3f base = m.base_color, emission = m.emission;
  float roughness = m.roughness, metallic = m.metallic;
  if constexpr (F::compiled(k_textures)) {
    if (features.on(k_textures) && s.uv != nullptr) {
      const Vec2f b = barycentric(corners, p);
      const Vec2f* c = s.uv + 3 * triangle;
      const Vec2f uv = c[0] * (1.0f - b.x - b.y) + c[1] * b.x + c[2] * b.y;
      const auto lookup = [&](int texture) {
        const TextureView& view = s.textures.views[texture];
        const float constant = triangle_lod_constant(corners.v0, corners.v1, corners.v2, c[0],
                                                     c[1], c[2], view.width, view.height);
        return sample_texture(s.textures, texture, uv,
                              cone_texture_lod(constant, cone, cos_incidence));
      };
      if (m.base_color_texture != k_no_texture) {
        const Vec4f t = lookup(m.base_color_texture);
        base = {base.x * t.x, base.y * t.y, base.z * t.z};
      }
      if (m.roughness_texture != k_no_texture) roughness *= lookup(m.roughness_texture).y;
      if (m.metallic_texture != k_no_texture) metallic *= lookup(m.metallic_texture).z;
      if (m.emission_texture != k_no_texture) {
        const Vec4f t = lookup(m.emission_texture);
        emission = {emission.x * t.x, emission.y * t.y, emission.z * t.z};
      }
    }
  }
  Bsdf bsdf{};
  bsdf.model = F::compiled(k_specular) ? m.model : MaterialModel::lambertian;
  bsdf.base_color = base;
  bsdf.metallic = metallic;
  bsdf.alpha = alpha_of(roughness);
  bsdf.ior = m.ior;
  bsdf.transmission = m.transmission;
  bsdf.eta = m.eta;
  bsdf.k = m.k;
  bsdf.conductor_f_avg = m.conductor_f_avg;
  return {bsdf, emission};
}
// [/listing:surface_at]

// Whether light passes through the surface: its frame is then the front face's (wo below it
// means the path arrives from inside), where an opaque surface turns its frame to the viewer.
RT_HD inline bool transmits(const Bsdf& b) {
  return b.model == MaterialModel::metallic_roughness && b.transmission > 0.0f &&
         b.metallic < 1.0f;
}

// What a bounce does to the ray's cone: a smooth lobe keeps it, a Lambertian surface widens it
// most, any other lobe by the material's alpha (glTF's diffuse lobe too: the course does not
// tell its lobes apart here, a heuristic that blurs less after a diffuse bounce off a shiny
// surface than after one off a Lambertian wall).
RT_HD inline ConeBounce cone_bounce(const Bsdf& bsdf, unsigned lobe) {
  if ((lobe & k_lobe_delta) != 0) return ConeBounce::specular;
  if (bsdf.model == MaterialModel::lambertian) return ConeBounce::diffuse;
  return ConeBounce::rough;
}

// [listing:lambertian_shortcut]
// The BSDF at one vertex, with chapter 11's Lambertian surface taken first: most of a room's
// hits are on its walls, and there the general mixture (five lobes and the choice between
// them) reduces to albedo * cos / pi, a cosine sample and its density. The answers are the
// mixture's; only the work is left out. Any other surface chooses its lobes once, for the
// vertex's wo, and its light sample and its bounce both use that choice.
struct VertexBsdf {
  Bsdf b;
  Vec3f wo;
  LobeChoice choice; // unused on a Lambertian surface
  RT_HD VertexBsdf(const Bsdf& bsdf, Vec3f w, const CompensationView& c)
      : b(bsdf), wo(w),
        choice(bsdf.model == MaterialModel::lambertian ? LobeChoice{}
                                                       : choose_lobes(bsdf, w, c)) {}
  RT_HD BsdfValue value(Vec3f wi, const CompensationView& c) const { // f |cos| and pdf
    if (b.model == MaterialModel::lambertian)
      return {wi.z > 0.0f ? b.base_color * (wi.z / ch11::k_pi) : Vec3f{},
              ch11::cosine_density(wi.z)};
    return bsdf_value(b, choice, wo, wi, c);
  }
  RT_UNFUSED_HD bool sample(float u_lobe, float u, float v, const CompensationView& c,
                            BsdfSample& out) const {
    if (b.model == MaterialModel::lambertian) {
      if (!(max_component(b.base_color) > 0.0f)) return false; // black: nothing comes back
      const Vec3f wi = ch07::cosine_direction_about_z(u, v);
      out = {wi, b.base_color, ch11::cosine_density(wi.z), k_lobe_reflect};
      return true;
    }
    return bsdf_sample(b, choice, wo, u_lobe, u, v, c, out);
  }
};
// [/listing:lambertian_shortcut]

// A shading frame: the normal and Duff's tangents (chapter 07).
struct Frame {
  Vec3f n;
  ch07::TangentFrame t;
  RT_HD Vec3f to_local(Vec3f w) const {
    return {dot(w, t.tangent), dot(w, t.bitangent), dot(w, n)};
  }
  RT_HD Vec3f to_world(Vec3f w) const {
    return normalize(t.tangent * w.x + t.bitangent * w.y + n * w.z);
  }
};

// The radiance an emitter sends from its point q: its material's emission, times its
// emission texture where it has one, read at level 0 (a shadow ray has no cone of its own;
// the light table picked the triangle by the factor alone, which bounds the texture's product).
template <class F>
RT_HD Vec3f emission_at(const MaterialSceneView& s, F features, int triangle,
                        const ch04::TriangleF& corners, Vec3f q) {
  const Material& m = s.surfaces[s.material[triangle]];
  Vec3f emission = m.emission;
  if constexpr (F::compiled(k_textures)) {
    if (features.on(k_textures) && s.uv != nullptr && m.emission_texture != k_no_texture) {
      const Vec2f b = barycentric(corners, q);
      const Vec2f* c = s.uv + 3 * triangle;
      const Vec2f uv = c[0] * (1.0f - b.x - b.y) + c[1] * b.x + c[2] * b.y;
      const Vec4f texel = sample_texture(s.textures, m.emission_texture, uv, 0.0f);
      emission = {emission.x * texel.x, emission.y * texel.y, emission.z * texel.z};
    }
  }
  return emission;
}

// [listing:material_next_event]
// Next-event estimation through a BSDF: chapter 11's point on an emitter, its contribution
// f(wo, wi) |cos| Le / pdf_light, weighed against the BSDF's density for the same direction.
// The density is the light table's, by the emission factor; Le is what the point emits.
template <class F>
RT_HD void sample_emitter_bsdf(const MaterialSceneView& s, F features, const PathState& path,
                               const ch11::VertexNumbers& u, Vec3f p, const Frame& frame,
                               const ch04::TriangleF& triangle, const VertexBsdf& bsdf,
                               Strategy strategy, ShadowRays& shadows) {
  const ch11::LightPoint light =
      ch11::sample_light_point(s, u.light_pick, u.light.x, u.light.y);
  const ch04::TriangleF& t = light.corners;
  const Vec3f guess = light.point - p; // which side of the surface the light is on
  const Vec3f side = dot(guess, frame.n) >= 0.0f ? frame.n : -frame.n;
  const Vec3f origin = ch11::spawn_origin(p, side, triangle);
  const Vec3f n_light = ch11::front_normal(t, origin - light.point);
  const Vec3f target = ch11::spawn_origin(light.point, n_light, t);
  const Vec3f to_light = target - origin;
  const float distance_squared = length_squared(to_light);
  const float distance = square_root(distance_squared);
  const Vec3f wi_world = to_light / distance;
  const float cos_q = dot(n_light, -wi_world);
  if (!(cos_q > 0.0f) || !(distance > 0.0f)) return; // edge-on, or behind the emitter
  const BsdfValue value = bsdf.value(frame.to_local(wi_world), s.compensation);
  const Vec3f f_cos = value.f_cos;
  if (!(max_component(f_cos) > 0.0f)) return;
  const Vec3f factor = s.materials[s.material[light.triangle]].emission;
  const float pdf_light = ch11::light_area_density(s, factor) * distance_squared / cos_q;
  const Vec3f emission = emission_at(s, features, light.triangle, t, light.point);
  const float weight =
      strategy == Strategy::mis ? ch11::power_heuristic(pdf_light, value.pdf) : 1.0f;
  const int k = shadows.count++;
  shadows.ray[k] = {origin, to_light, 0.0f, 1.0f};
  shadows.contribution[k] = path.throughput * f_cos * emission * (weight / pdf_light);
}
// [/listing:material_next_event]

// [listing:material_shade_vertex]
template <class F>
RT_HD bool shade_vertex(const MaterialSceneView& s, F features, Strategy strategy,
                        MaterialPath& path, const TraceHit& hit, ShadowRays& shadows) {
  using namespace ch11;
  const Vec3f d = path.ray.direction;
  if (hit.triangle < 0) { // the ray left the scene
    if constexpr (F::compiled(k_sky))
      if (features.on(k_sky)) path.radiance += path.throughput * s.environment.sky;
    return false;
  }
  ++path.vertex;
  const ch04::TriangleF triangle = s.mesh.triangle(hit.triangle);
  const Vec3f front = front_normal(triangle, -d);
  const bool from_front = dot(front, d) < 0.0f;
  const Vec3f p = path.ray.origin + d * hit.t;
  const Material& m = s.surfaces[s.material[hit.triangle]];
  path.cone = propagate(path.cone, hit.t); // the footprint here (ray_cone.h)
  const SurfaceAt surface =
      surface_at(s, features, m, hit.triangle, triangle, p, path.cone, dot(front, d));
  const Bsdf& bsdf = surface.bsdf;
  if constexpr (F::compiled(k_emitters)) { // emits from the front only, as chapter 11
    // the camera ray, or a bounce of a smooth lobe (bsdf_pdf 0), weighs 1
    if (features.on(k_emitters) && from_front && max_component(surface.emission) > 0.0f)
      path.radiance += path.throughput * surface.emission *
                       emitter_hit_weight(s, path, strategy, m.emission, dot(front, d), hit.t);
  }
  // The frame: the front face's for a surface light passes through (wo below it: inside),
  // else turned to the viewer (surfaces reflect on both sides, as chapter 11's).
  const Vec3f n = transmits(bsdf) || from_front ? front : -front;
  const Frame frame{n, ch07::duff_frame(n)};
  const Vec3f wo = frame.to_local(-d);
  const VertexBsdf scatter(bsdf, wo, s.compensation); // its lobes chosen once, for this wo
  const bool smooth_only = bsdf_is_delta_only(bsdf);
  bool next_event = false; // a shadow ray to a point on an emitter
  if constexpr (F::compiled(k_emitters))
    next_event = features.on(k_emitters) && strategy != Strategy::bsdf && s.light_count > 0 &&
                 !smooth_only;
  const bool roulette = path.vertex >= ch11::k_roulette_from_vertex;
  // The vertex's numbers (chapter 11's VertexNumbers); the spare pair's first is the lobe's.
  const ch11::VertexNumbers u =
      ch11::vertex_numbers(s.sampler, path,
                           ch11::k_pad_bsdf | ch11::k_pad_spare |
                               (next_event || roulette ? ch11::k_pad_roulette : 0u) |
                               (next_event ? ch11::k_pad_light : 0u));
  static_assert(k_lobe_pick == 6, "the lobe pick is the spare pad's first number");
  if constexpr (F::compiled(k_sun)) {
    const Environment& e = s.environment;
    if (features.on(k_sun) && !smooth_only) {
      const Vec3f wi = frame.to_local(e.sun_direction);
      const Vec3f f_cos = scatter.value(wi, s.compensation).f_cos;
      if (max_component(f_cos) > 0.0f) {
        const int k = shadows.count++;
        const Vec3f side = wi.z >= 0.0f ? n : -n;
        shadows.ray[k] = {spawn_origin(p, side, triangle), e.sun_direction};
        shadows.contribution[k] = path.throughput * f_cos * e.sun_irradiance;
      }
    }
  }
  if constexpr (F::compiled(k_emitters))
    if (next_event)
      sample_emitter_bsdf(s, features, path, u, p, frame, triangle, scatter, strategy, shadows);
  // The bounce: the BSDF's own sample, its weight f |cos| / pdf.
  BsdfSample bounce;
  if (!scatter.sample(u.spare.x, u.bsdf.x, u.bsdf.y, s.compensation, bounce)) return false;
  path.throughput = path.throughput * bounce.weight;
  // [listing:roulette_eta]
  // Russian roulette as chapter 11's, on the throughput with the refractions' radiance scaling
  // taken out (pbrt's etaScale). Entering glass divides the throughput by 2.25 and leaving it
  // multiplies it back: judged on the scaled throughput, a path inside glass is ended too
  // often, and one that has left it carries 2.25 times its worth and survives at the cap every
  // time after, bounce after bounce, long after it has anything left to bring back.
  if ((bounce.lobe & k_lobe_transmit) != 0 && bsdf.ior != 1.0f) {
    const float eta = wo.z > 0.0f ? bsdf.ior : 1.0f / bsdf.ior; // inside over outside
    path.eta_scale *= eta * eta;
  }
  if (!survives_roulette(path, u.roulette, path.eta_scale)) return false;
  // [/listing:roulette_eta]
  const Vec3f direction = frame.to_world(bounce.wi);
  const Vec3f side = bounce.wi.z >= 0.0f ? n : -n;
  path.ray = {spawn_origin(p, side, triangle), direction};
  path.bsdf_pdf = (bounce.lobe & k_lobe_delta) != 0 ? 0.0f : bounce.pdf;
  path.cone = bounce_cone(path.cone, cone_bounce(bsdf, bounce.lobe), bsdf.alpha);
  return true;
}
// [/listing:material_shade_vertex]

} // namespace rt::ch12
