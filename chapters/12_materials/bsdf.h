// Chapter 12: what a surface does with light, in its local frame (z is the normal). Each model
// is a sum of lobes: a Lambertian one, GGX reflection off a metal or off a dielectric coat,
// transmission through a rough or smooth dielectric (Walter et al. 2007), and the energy
// compensation of rough metals (a lobe) and of rough glass (a scale). The sampler picks one
// lobe, draws from it, and weights the direction by the whole sum, so eval, pdf and sample
// always agree.
#pragma once

#include <limits>

#include "energy_compensation.h"
#include "material.h"
#include "microfacet.h"
#include "path_sampling.h"
#include "rt/hd.h"
#include "rt/vec.h"

namespace rt::ch12 {

// [listing:bsdf]
// The material at one hit, its textures already applied (filled from Material).
struct Bsdf {
  MaterialModel model;
  Vec3f base_color;                         // linear
  float metallic, alpha, ior, transmission; // alpha = roughness^2 (0: smooth)
  Vec3f eta, k, conductor_f_avg;            // model conductor
};

enum Lobe : unsigned { k_lobe_reflect = 1, k_lobe_transmit = 2, k_lobe_delta = 4 };

struct BsdfSample {
  Vec3f wi;      // unit, local frame
  Vec3f weight;  // f |cos wi| / pdf (for a delta lobe: the lobe's weight / its choice prob.)
  float pdf;     // solid-angle density of wi (0 for a delta lobe: not comparable)
  unsigned lobe; // Lobe bits
};
// [/listing:bsdf]

// The lobes a model is made of. Lambertian: diffuse. Conductor: metal and its compensation.
// glTF metallic-roughness: metallic times (metal + compensation) plus (1 - metallic) times
// the dielectric: (1 - transmission) (diffuse under a specular coat) + transmission (a rough
// or smooth dielectric interface, its refraction tinted by the base colour).
enum class LobeKind : int {
  diffuse,            // Lambertian; under glTF's coat, times (1 - F)
  coat,               // GGX reflection off the dielectric, glTF's Schlick F
  dielectric,         // GGX reflection and refraction through it, the exact F (Walter 2007)
  metal,              // GGX reflection off the metal: Schlick F0 = base colour, or eta + i k
  metal_compensation, // Kulla-Conty's multiple-scattering lobe of the metal
  count
};
inline constexpr int k_lobe_kinds = static_cast<int>(LobeKind::count);

// ---------------------------------------------------------------------------------------------
// Parts every lobe uses.

RT_HD inline bool is_smooth(const Bsdf& b) { return b.alpha < k_smooth_alpha; }

// An interface between equal indices is no interface: light passes straight through, whatever
// the roughness (every microfacet refracts wo into -wo), so the transmission is a delta lobe.
RT_HD inline bool dielectric_is_delta(const Bsdf& b) { return is_smooth(b) || b.ior == 1.0f; }

// The opaque lobes are two-sided: seen from below (wo.z < 0, which only a transmissive model
// lets through) they are the mirror image of the lobe above.
RT_HD inline Vec3f to_side_of(Vec3f w, float side_z) {
  return side_z < 0.0f ? Vec3f{w.x, w.y, -w.z} : w;
}

// glTF's Fresnel term of the coat: Schlick with F0 = ((1 - ior) / (1 + ior))^2. At ior exactly
// 1 the coat is no interface, and reflects nothing (Schlick's grazing term would).
RT_HD inline float coat_fresnel(float ior, float cosine) {
  if (ior == 1.0f) return 0.0f;
  const float f0 = dielectric_f0(ior);
  return f0 + (1.0f - f0) * schlick_weight(cosine);
}

// The metal's Fresnel term at the cosine between the view and a microfacet.
RT_HD inline Vec3f metal_fresnel(const Bsdf& b, float cosine) {
  if (b.model == MaterialModel::conductor) return fresnel_conductor(cosine, b.eta, b.k);
  return fresnel_schlick(b.base_color, cosine);
}
RT_HD inline Vec3f metal_f_avg(const Bsdf& b) {
  return b.model == MaterialModel::conductor ? b.conductor_f_avg : schlick_f_avg(b.base_color);
}

// What each lobe is scaled by in the model's sum.
RT_HD inline float lobe_scale(const Bsdf& b, LobeKind kind) {
  const float dielectric = 1.0f - b.metallic;
  switch (b.model) {
  case MaterialModel::lambertian:
    return kind == LobeKind::diffuse ? 1.0f : 0.0f;
  case MaterialModel::conductor:
    return kind == LobeKind::metal || kind == LobeKind::metal_compensation ? 1.0f : 0.0f;
  default:
    break;
  }
  switch (kind) {
  case LobeKind::diffuse:
  case LobeKind::coat:
    return dielectric * (1.0f - b.transmission);
  case LobeKind::dielectric:
    return dielectric * b.transmission;
  default:
    return b.metallic;
  }
}

RT_HD inline bool compensates(const Bsdf& b, const CompensationView& table) {
  return table.enabled && !is_smooth(b);
}

// [listing:dielectric_compensation]
// Rough glass loses light as a rough metal does: one scattering off the microfacets keeps
// E(mu_o, alpha, eta) of what arrives from wo, reflected and refracted together, and the rest
// would have scattered again between the facets. Turquin 2019: scale the whole dielectric
// lobe by 1 / E, so that from every wo it keeps all of it. The scale depends on wo alone, so
// the lobe's shape and its sampler stay as they are; the price is reciprocity, which the
// scaled lobe keeps only where E(wo) = E(wi). eta is the index of the far side over wo's.
RT_HD inline float dielectric_compensation(const Bsdf& b, Vec3f wo,
                                           const CompensationView& table) {
  if (!compensates(b, table)) return 1.0f;
  const float eta = wo.z > 0.0f ? b.ior : 1.0f / b.ior;
  const float kept = dielectric_directional_albedo(table, absolute(wo.z), b.alpha, eta);
  return kept > 0.0f ? 1.0f / kept : 1.0f;
}
// [/listing:dielectric_compensation]

// [listing:lobe_choice]
// How often the sampler picks each lobe for this wo: an estimate of the light each returns
// (the Fresnel term at wo's own cosine, the albedo of the diffuse, E and 1 - E for the metal
// and its compensation). Any choice is unbiased, as long as a lobe that can return light can
// be picked: the weights only move noise between the lobes.
struct LobeChoice {
  float probability[k_lobe_kinds];
};
RT_HD inline LobeChoice choose_lobes(const Bsdf& b, Vec3f wo, const CompensationView& table) {
  const float cosine = absolute(wo.z);
  float weight[k_lobe_kinds] = {};
  const float coat = coat_fresnel(b.ior, cosine);
  weight[int(LobeKind::diffuse)] =
      lobe_scale(b, LobeKind::diffuse) * (1.0f - coat) * ch11::luminance(b.base_color);
  weight[int(LobeKind::coat)] = lobe_scale(b, LobeKind::coat) * coat;
  weight[int(LobeKind::dielectric)] = lobe_scale(b, LobeKind::dielectric);
  const float single =
      compensates(b, table) ? directional_albedo(table, cosine, b.alpha) : 1.0f;
  weight[int(LobeKind::metal)] = lobe_scale(b, LobeKind::metal) * single;
  weight[int(LobeKind::metal_compensation)] =
      compensates(b, table) ? lobe_scale(b, LobeKind::metal_compensation) * (1.0f - single)
                            : 0.0f;
  float total = 0.0f;
  for (const float w : weight) total += w;
  LobeChoice choice{};
  if (total > 0.0f)
    for (int i = 0; i < k_lobe_kinds; ++i) // 0 / total is 0: skip the division
      choice.probability[i] = weight[i] == 0.0f ? 0.0f : weight[i] / total;
  return choice;
}
// [/listing:lobe_choice]

// ---------------------------------------------------------------------------------------------
// GGX reflection, shared by the coat and the metal: f cos = D(h) G2 F / (4 cos_o), sampled by
// reflecting wo about a visible normal, with density D_wo(h) / (4 wo.h). wo and wi on the
// upper side; returns the half vector for the Fresnel term.

RT_HD inline bool reflection_half_vector(Vec3f wo, Vec3f wi, Vec3f& h) {
  if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return false;
  h = normalize(wo + wi);
  return true;
}
RT_HD inline float ggx_reflection(Vec3f wo, Vec3f wi, Vec3f h, float alpha) {
  return ggx_d(h, alpha) * smith_g2(wo, wi, alpha) / (4.0f * wo.z);
}
RT_HD inline float ggx_reflection_pdf(Vec3f wo, Vec3f h, float alpha) {
  const float facing = dot(wo, h);
  return facing > 0.0f ? visible_normal_density(wo, h, alpha) / (4.0f * facing) : 0.0f;
}

// ---------------------------------------------------------------------------------------------
// [listing:dielectric]
// Walter et al. 2007, a rough dielectric interface. Its index is ior inside (below z = 0)
// and 1 outside. A reflection's microfacet is the half vector; a refraction's is the
// generalised half vector wi eta' + wo, where eta' is the index of wi's side over wo's.
// Radiance crossing into wo's side is scaled by (eta_wo / eta_wi)^2 = 1 / eta'^2: it spreads
// over a wider cone when it leaves a denser medium.
struct DielectricGeometry {
  Vec3f m;        // the microfacet normal, on the outside
  float eta;      // eta' (1 for a reflection)
  bool reflected; // wo and wi on the same side
};
RT_HD inline bool dielectric_geometry(Vec3f wo, Vec3f wi, float ior, DielectricGeometry& g) {
  if (wo.z == 0.0f || wi.z == 0.0f) return false;
  g.reflected = wo.z * wi.z > 0.0f;
  g.eta = g.reflected ? 1.0f : (wo.z > 0.0f ? ior : 1.0f / ior);
  const Vec3f m = wi * g.eta + wo;
  const float length2 = length_squared(m);
  if (!(length2 > 0.0f)) return false;
  g.m = m / square_root(length2);
  if (g.m.z < 0.0f) g.m = -g.m;
  // Both directions on the microfacet's own sides: a microfacet seen from behind neither
  // reflects nor refracts.
  return dot(g.m, wi) * wi.z > 0.0f && dot(g.m, wo) * wo.z > 0.0f;
}

RT_HD inline Vec3f dielectric_eval(const Bsdf& b, Vec3f wo, Vec3f wi) {
  DielectricGeometry g;
  if (!dielectric_geometry(wo, wi, b.ior, g)) return {};
  const float fresnel = fresnel_dielectric(dot(wo, g.m), b.ior);
  const float d = ggx_d(g.m, b.alpha), g2 = smith_g2(wo, wi, b.alpha);
  if (g.reflected) {
    const float f = d * g2 * fresnel / (4.0f * absolute(wo.z));
    return {f, f, f};
  }
  const float wi_m = dot(wi, g.m), wo_m = dot(wo, g.m);
  const float denominator = wi_m + wo_m / g.eta;
  const float f = d * (1.0f - fresnel) * g2 * absolute(wi_m * wo_m) /
                  (denominator * denominator * absolute(wo.z)) / (g.eta * g.eta);
  return b.base_color * f;
}

RT_HD inline float dielectric_pdf(const Bsdf& b, Vec3f wo, Vec3f wi) {
  DielectricGeometry g;
  if (!dielectric_geometry(wo, wi, b.ior, g)) return 0.0f;
  const float fresnel = fresnel_dielectric(dot(wo, g.m), b.ior);
  const float visible = visible_normal_density(wo, g.m, b.alpha);
  if (g.reflected) return visible / (4.0f * absolute(dot(wo, g.m))) * fresnel;
  const float wi_m = dot(wi, g.m);
  const float denominator = wi_m + dot(wo, g.m) / g.eta;
  return visible * absolute(wi_m) / (denominator * denominator) * (1.0f - fresnel);
}

// A microfacet from wo's visible normals, then reflection or refraction by its Fresnel term.
RT_UNFUSED_HD inline bool dielectric_sample(const Bsdf& b, Vec3f wo, float u_choice, float u,
                                            float v, Vec3f& wi) {
  const Vec3f m = sample_visible_normal_caps(wo, b.alpha, u, v);
  const float fresnel = fresnel_dielectric(dot(wo, m), b.ior);
  if (u_choice < fresnel) {
    wi = normalize(reflect(wo, m));
    return wi.z * wo.z > 0.0f;
  }
  if (!refract(wo, m, b.ior, wi)) return false;
  wi = normalize(wi);
  return wi.z * wo.z < 0.0f;
}
// [/listing:dielectric]

// ---------------------------------------------------------------------------------------------
// [listing:bsdf_eval]
// f(wo, wi) |wi.z| and the density of bsdf_sample's wi, in one pass over the lobes: the sum
// of the non-delta lobes (a delta lobe is never hit by a direction chosen elsewhere), and
// their densities weighted by how often `choice` picks each (choose_lobes for this wo). The
// reflection lobes share their geometry: wo and wi turned to wo's side, the half vector, the
// coat's Fresnel term, GGX's reflection (the coat's and the metal's, at one alpha) and its
// density. Each is computed once for the whole sum, not once per lobe.
struct BsdfValue {
  Vec3f f_cos; // f(wo, wi) |wi.z|
  float pdf;   // bsdf_sample's solid-angle density of wi
};
RT_HD inline BsdfValue bsdf_value(const Bsdf& b, const LobeChoice& choice, Vec3f wo, Vec3f wi,
                                  const CompensationView& table) {
  const float* picked = choice.probability;
  const float diffuse = lobe_scale(b, LobeKind::diffuse), coat = lobe_scale(b, LobeKind::coat);
  const float dielectric = lobe_scale(b, LobeKind::dielectric);
  const float metal = lobe_scale(b, LobeKind::metal);
  const float compensation = lobe_scale(b, LobeKind::metal_compensation);
  const Vec3f o = to_side_of(wo, wo.z), i = to_side_of(wi, wo.z);
  Vec3f h;
  const bool reflects = reflection_half_vector(o, i, h);
  const float fresnel =
      reflects && b.model != MaterialModel::lambertian ? coat_fresnel(b.ior, dot(o, h)) : 0.0f;
  const bool glossy = reflects && !is_smooth(b); // GGX reflection, not a mirror
  const float ggx =
      glossy && (coat > 0.0f || metal > 0.0f) ? ggx_reflection(o, i, h, b.alpha) : 0.0f;
  const bool rough_interface = !dielectric_is_delta(b);

  BsdfValue v{};
  if (reflects && diffuse > 0.0f)
    v.f_cos += b.base_color * (diffuse * (1.0f - fresnel) * i.z / ch11::k_pi);
  if (glossy && coat > 0.0f) v.f_cos += Vec3f{1.0f, 1.0f, 1.0f} * (coat * fresnel * ggx);
  if (rough_interface && dielectric > 0.0f)
    v.f_cos +=
        dielectric_eval(b, wo, wi) * (dielectric * dielectric_compensation(b, wo, table));
  if (glossy && metal > 0.0f) v.f_cos += metal_fresnel(b, dot(o, h)) * (metal * ggx);
  if (reflects && compensation > 0.0f && compensates(b, table))
    v.f_cos += compensation_colour(metal_f_avg(b), average_albedo(table, b.alpha)) *
               (compensation * compensation_lobe(table, o.z, i.z, b.alpha));

  const float cosine_pdf = reflects ? ch11::cosine_density(i.z) : 0.0f;
  const float ggx_pdf =
      glossy && (picked[int(LobeKind::coat)] > 0.0f || picked[int(LobeKind::metal)] > 0.0f)
          ? ggx_reflection_pdf(o, h, b.alpha)
          : 0.0f;
  const float lobe_pdf[k_lobe_kinds] = {
      cosine_pdf, ggx_pdf,
      rough_interface && picked[int(LobeKind::dielectric)] > 0.0f ? dielectric_pdf(b, wo, wi)
                                                                  : 0.0f,
      ggx_pdf, cosine_pdf};
  for (int kind = 0; kind < k_lobe_kinds; ++kind)
    if (picked[kind] > 0.0f) v.pdf += picked[kind] * lobe_pdf[kind];
  return v;
}

// Each alone, for a caller that needs one of them.
RT_HD inline Vec3f bsdf_eval(const Bsdf& b, Vec3f wo, Vec3f wi, const CompensationView& table) {
  return bsdf_value(b, choose_lobes(b, wo, table), wo, wi, table).f_cos;
}
RT_HD inline float bsdf_pdf(const Bsdf& b, Vec3f wo, Vec3f wi, const CompensationView& table) {
  return bsdf_value(b, choose_lobes(b, wo, table), wo, wi, table).pdf;
}
// [/listing:bsdf_eval]

// True if some lobe of the material is a delta distribution (a mirror, a smooth interface).
RT_HD inline bool bsdf_has_smooth_lobe(const Bsdf& b) {
  if (b.model == MaterialModel::lambertian) return false;
  if (b.model == MaterialModel::conductor) return is_smooth(b);
  return (is_smooth(b) && (b.metallic > 0.0f || b.transmission < 1.0f)) ||
         (dielectric_is_delta(b) && lobe_scale(b, LobeKind::dielectric) > 0.0f);
}

// True if every lobe is a delta distribution: next-event estimation can find nothing.
RT_HD inline bool bsdf_is_delta_only(const Bsdf& b) {
  if (b.model == MaterialModel::lambertian) return false;
  if (!is_smooth(b)) { // only an ior-1 interface is a delta lobe on a rough surface
    return b.model == MaterialModel::metallic_roughness && b.metallic == 0.0f &&
           b.transmission == 1.0f && b.ior == 1.0f;
  }
  return lobe_scale(b, LobeKind::diffuse) * ch11::luminance(b.base_color) == 0.0f;
}

// [listing:bsdf_sample]
// Pick a lobe with u_lobe (and reuse what is left of u_lobe inside the lobe's interval for
// the dielectric's reflect-or-refract), draw wi from it with u and v, and weight wi by the
// whole sum: f(wi) |cos| / pdf(wi) over all non-delta lobes. A delta lobe's direction is met
// by no other lobe: its weight is its own, over the chance of picking it.
RT_UNFUSED_HD inline bool bsdf_sample(const Bsdf& b, const LobeChoice& choice, Vec3f wo,
                                      float u_lobe, float u, float v,
                                      const CompensationView& table, BsdfSample& out) {
  // The lobe whose interval holds u_lobe; rounding may leave the last interval short of 1,
  // so a u_lobe past every interval takes the last lobe that can be picked.
  int kind = -1;
  float start = 0.0f, kind_start = 0.0f;
  for (int k = 0; k < k_lobe_kinds; ++k) {
    if (!(choice.probability[k] > 0.0f)) continue;
    kind = k;
    kind_start = start;
    if (u_lobe < start + choice.probability[k]) break;
    start += choice.probability[k];
  }
  if (kind < 0) return false; // a black surface
  const float probability = choice.probability[kind];
  const float u_inside = clamp_to((u_lobe - kind_start) / probability, 0.0f, 0.99999994f);
  const LobeKind lobe = LobeKind(kind);
  const float scale = lobe_scale(b, lobe);
  const Vec3f o = to_side_of(wo, wo.z);
  const Vec3f mirror{-wo.x, -wo.y, wo.z};

  if (lobe == LobeKind::dielectric && dielectric_is_delta(b)) {
    const float fresnel = fresnel_dielectric(wo.z, b.ior);
    if (u_inside < fresnel) { // the weight F / (the chance F of choosing it)
      out = {mirror, Vec3f{1.0f, 1.0f, 1.0f} * (scale / probability), 0.0f,
             k_lobe_reflect | k_lobe_delta};
      return true;
    }
    Vec3f wt;
    if (!refract(wo, Vec3f{0.0f, 0.0f, 1.0f}, b.ior, wt)) return false;
    const float eta = wo.z > 0.0f ? b.ior : 1.0f / b.ior;
    // b.ior == 1: wt is -wo exactly (refract's arithmetic with eta 1), weight the tint.
    out = {b.ior == 1.0f ? -wo : normalize(wt),
           b.base_color * (scale / (probability * eta * eta)), 0.0f,
           k_lobe_transmit | k_lobe_delta};
    return true;
  }
  if (is_smooth(b) && (lobe == LobeKind::coat || lobe == LobeKind::metal)) {
    const Vec3f f = lobe == LobeKind::coat ? Vec3f{1.0f, 1.0f, 1.0f} * coat_fresnel(b.ior, o.z)
                                           : metal_fresnel(b, o.z);
    out = {mirror, f * (scale / probability), 0.0f, k_lobe_reflect | k_lobe_delta};
    return true;
  }

  Vec3f wi;
  switch (lobe) {
  case LobeKind::dielectric:
    if (!dielectric_sample(b, wo, u_inside, u, v, wi)) return false;
    break;
  case LobeKind::diffuse:
  case LobeKind::metal_compensation:
    wi = to_side_of(ch07::cosine_direction_about_z(u, v), wo.z);
    break;
  default:
    wi = to_side_of(normalize(reflect(o, sample_visible_normal_caps(o, b.alpha, u, v))), wo.z);
    if (!(wi.z * wo.z > 0.0f)) return false; // reflected below the horizon
    break;
  }
  const BsdfValue value = bsdf_value(b, choice, wo, wi, table);
  const float pdf = value.pdf;
  if (!(pdf > 0.0f) || !(pdf <= std::numeric_limits<float>::max())) return false;
  out = {wi, value.f_cos / pdf, pdf,
         wi.z * wo.z > 0.0f ? unsigned(k_lobe_reflect) : unsigned(k_lobe_transmit)};
  return true;
}
// [/listing:bsdf_sample]

// The sampler with the lobes chosen for this wo (a caller that has no choice of its own).
RT_UNFUSED_HD inline bool bsdf_sample(const Bsdf& b, Vec3f wo, float u_lobe, float u, float v,
                                      const CompensationView& table, BsdfSample& out) {
  return bsdf_sample(b, choose_lobes(b, wo, table), wo, u_lobe, u, v, table, out);
}

} // namespace rt::ch12
