// Chapter 12: the microfacet model every rough material of the chapter is made of. A rough
// surface is a field of tiny mirrors whose normals m follow the isotropic GGX (Trowbridge-
// Reitz) distribution D(m); Smith's shadowing term G says how many of them the light and the
// eye both see; the Fresnel term F says how much each mirror reflects. Everything is in the
// local frame of the surface, whose z axis is the normal, so cos(theta) of a direction is its
// z.
#pragma once

#include <numbers>

#include "cosine_sampling.h"
#include "rt/hd.h"
#include "rt/scalar.h"
#include "rt/vec.h"

namespace rt::ch12 {

template <class T> inline constexpr T k_pi_of = std::numbers::pi_v<T>;

// sin^2(theta) of a direction from its own components, never as 1 - cos^2(theta): near the
// normal 1 - cos^2 cancels to nothing, and a narrow lobe (alpha 1e-4) lives exactly there.
template <class T> RT_HD inline T sin2_theta(Vec3<T> w) { return w.x * w.x + w.y * w.y; }

// [listing:ggx_d]
// The GGX distribution of normals, D(m) = 1 / (pi alpha^2 cos^4 (1 + tan^2 / alpha^2)^2).
// With tan^2 = sin^2 / cos^2 multiplied out by cos^4 it reads alpha^2 / (pi (alpha^2 cos^2 +
// sin^2)^2): no tangent to overflow at grazing m (cos 1e-6), no 1 - cos^2 to cancel near the
// normal, and a finite peak 1 / (pi alpha^2) however small alpha is. Zero below the surface.
template <class T> RT_HD inline T ggx_d(Vec3<T> m, T alpha) {
  if (!(m.z > T(0))) return T(0);
  const T alpha2 = alpha * alpha;
  const T denominator = alpha2 * m.z * m.z + sin2_theta(m);
  return alpha2 / (k_pi_of<T> * denominator * denominator);
}
// [/listing:ggx_d]

// The term sqrt(cos^2 + alpha^2 sin^2) that Smith's Lambda and G are made of: Lambda(w) =
// (sqrt(1 + alpha^2 tan^2) - 1) / 2 = (smith_root / |cos| - 1) / 2. Writing G through it,
// not through Lambda, keeps the grazing case (cos -> 0, Lambda -> inf) finite.
template <class T> RT_HD inline T smith_root(Vec3<T> w, T alpha) {
  return square_root(w.z * w.z + alpha * alpha * sin2_theta(w));
}

// Smith's Lambda for GGX: the ratio of the shadowed to the visible projected area of the
// microfacets seen from w. Infinite at exactly grazing w (callers use G1 and G2 instead).
template <class T> RT_HD inline T smith_lambda(Vec3<T> w, T alpha) {
  const T cosine = absolute(w.z);
  return T(0.5) * (smith_root(w, alpha) / cosine - T(1));
}

// G1(w) = 1 / (1 + Lambda(w)) = 2 |cos| / (|cos| + smith_root): the share of the microfacets
// facing w that w sees. 0 at grazing, 1 at the normal, never 0 / 0 (smith_root >= |cos|).
template <class T> RT_HD inline T smith_g1(Vec3<T> w, T alpha) {
  const T cosine = absolute(w.z);
  const T denominator = cosine + smith_root(w, alpha);
  return denominator > T(0) ? T(2) * cosine / denominator : T(0);
}

// [listing:smith_g2]
// The height-correlated masking-shadowing term G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz
// 2014): a microfacet high on the surface is likelier to be seen from both directions at
// once. Multiplied through by 2 |cos_o| |cos_i| it has no infinity at grazing.
template <class T> RT_HD inline T smith_g2(Vec3<T> wo, Vec3<T> wi, T alpha) {
  const T cos_o = absolute(wo.z), cos_i = absolute(wi.z);
  const T denominator = cos_i * smith_root(wo, alpha) + cos_o * smith_root(wi, alpha);
  return denominator > T(0) ? T(2) * cos_o * cos_i / denominator : T(0);
}
// [/listing:smith_g2]

// wo turned to the upper side of the surface: the microfacets it sees are those it would see
// from there (the distribution is symmetric), as when a ray arrives from inside glass.
template <class T> RT_HD inline Vec3<T> to_upper_side(Vec3<T> w) { return w.z < T(0) ? -w : w; }

// The density of the visible normals seen from wo, D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z
// (Heitz 2014): the normals weighted by the area they show wo. It integrates to 1 over m, and
// both samplers below draw from it. wo below the surface sees what -wo sees.
template <class T> RT_HD inline T visible_normal_density(Vec3<T> wo, Vec3<T> m, T alpha) {
  const Vec3<T> w = to_upper_side(wo);
  const T facing = dot(w, m);
  if (!(facing > T(0)) || !(w.z > T(0))) return T(0);
  return smith_g1(w, alpha) * facing * ggx_d(m, alpha) / w.z;
}

// The normal of the GGX surface stretched by 1 / alpha: the hemisphere's. Shared by both
// samplers, which draw on the unit hemisphere and stretch the result back (and by the
// quadrature of the glass's compensation table, in double).
template <class T> RT_HD inline Vec3<T> stretched(Vec3<T> w, T alpha) {
  return normalize(Vec3<T>{alpha * w.x, alpha * w.y, w.z});
}
template <class T> RT_HD inline Vec3<T> unstretched_normal(Vec3<T> n, T alpha) {
  const Vec3<T> m{alpha * n.x, alpha * n.y, max_of(n.z, T(0))};
  const T length2 = length_squared(m);
  // A normal squeezed to nothing (n exactly on the horizon at a tiny alpha) is the horizon's
  // limit; the normal is what a zero-length vector would have meant.
  return length2 > T(0) ? m / square_root(length2) : Vec3<T>{T(0), T(0), T(1)};
}

// [listing:vndf_heitz]
// Heitz 2018, "Sampling the GGX Distribution of Visible Normals": stretch the view to the
// hemisphere configuration (alpha = 1), where the visible normals project to a disk seen from
// wo; draw a point on that disk, squashed on the half the hemisphere hides; lift it to the
// hemisphere and stretch the normal back. u, v uniform in [0, 1).
RT_UNFUSED_HD inline Vec3f sample_visible_normal_heitz(Vec3f wo, float alpha, float u,
                                                       float v) {
  const Vec3f view = stretched(to_upper_side(wo), alpha);
  const float length2 = view.x * view.x + view.y * view.y;
  const Vec3f t1 = length2 > 0.0f ? Vec3f{-view.y, view.x, 0.0f} / square_root(length2)
                                  : Vec3f{1.0f, 0.0f, 0.0f};
  const Vec3f t2 = cross(view, t1);
  const float radius = square_root(u);
  const ch07::SinCos phi = ch07::sin_cos_turns(v);
  const float p1 = radius * phi.cos;
  const float s = 0.5f * (1.0f + view.z);
  const float p2 =
      (1.0f - s) * square_root(max_of(0.0f, 1.0f - p1 * p1)) + s * radius * phi.sin;
  const float p3 = square_root(max_of(0.0f, 1.0f - p1 * p1 - p2 * p2));
  return unstretched_normal(t1 * p1 + t2 * p2 + view * p3, alpha);
}
// [/listing:vndf_heitz]

// [listing:vndf_caps]
// Dupuy and Benyoub 2023, "Sampling Visible GGX Normals with Spherical Caps": in the
// hemisphere configuration the reflected directions of the visible normals are uniform on the
// spherical cap z > -view.z, and the normal is the half vector of the view and such a
// direction. No frame to build and no branch. u, v uniform in [0, 1).
RT_UNFUSED_HD inline Vec3f sample_visible_normal_caps(Vec3f wo, float alpha, float u, float v) {
  const Vec3f view = stretched(to_upper_side(wo), alpha);
  const float z = (1.0f - v) * (1.0f + view.z) - view.z; // uniform in (-view.z, 1]
  const float sin_theta = square_root(max_of(0.0f, (1.0f - z) * (1.0f + z)));
  const ch07::SinCos phi = ch07::sin_cos_turns(u);
  const Vec3f cap{sin_theta * phi.cos, sin_theta * phi.sin, z};
  return unstretched_normal(cap + view, alpha); // unnormalised: the stretch normalises
}
// [/listing:vndf_caps]

// ---------------------------------------------------------------------------------------------
// Fresnel: the share of light a smooth interface reflects, by the cosine of the angle of
// incidence on it.

// Schlick's approximation with the reflectance F0 at normal incidence (a colour for metals).
RT_HD inline float schlick_weight(float cosine) {
  const float c = 1.0f - clamp_to(cosine, 0.0f, 1.0f);
  const float c2 = c * c;
  return c2 * c2 * c;
}
RT_HD inline Vec3f fresnel_schlick(Vec3f f0, float cosine) {
  const float w = schlick_weight(cosine);
  return f0 + (Vec3f{1.0f, 1.0f, 1.0f} - f0) * w;
}

// F0 of the interface from air into a dielectric of index ior: ((1 - ior) / (1 + ior))^2.
RT_HD inline float dielectric_f0(float ior) {
  const float r = (1.0f - ior) / (1.0f + ior);
  return r * r;
}

// [listing:fresnel_dielectric]
// The exact Fresnel reflectance of unpolarised light at a smooth dielectric interface.
// cos_i is the cosine of the incident direction with the normal; eta = eta_t / eta_i, the
// index of the side opposite the normal over the index of the normal's side, for light on
// the normal's side (cos_i > 0); for cos_i < 0 the function swaps the sides itself. Past the
// critical angle all light is reflected (total internal reflection); with eta exactly 1
// there is no interface at all, and nothing is reflected.
template <class T> RT_HD inline T fresnel_dielectric(T cos_i, T eta) {
  if (eta == T(1)) return T(0);
  if (cos_i < T(0)) {
    eta = T(1) / eta;
    cos_i = -cos_i;
  }
  cos_i = min_of(cos_i, T(1));
  const T sin2_t = (T(1) - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= T(1)) return T(1);
  const T cos_t = square_root(T(1) - sin2_t);
  const T parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const T perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return T(0.5) * (parallel * parallel + perpendicular * perpendicular);
}
// [/listing:fresnel_dielectric]

// A complex number, only as much of one as the conductor's Fresnel term needs (std::complex
// has no device side).
template <class T> struct Complex { T re{}, im{}; };
template <class T> RT_HD inline Complex<T> operator+(Complex<T> a, Complex<T> b) {
  return {a.re + b.re, a.im + b.im};
}
template <class T> RT_HD inline Complex<T> operator-(Complex<T> a, Complex<T> b) {
  return {a.re - b.re, a.im - b.im};
}
template <class T> RT_HD inline Complex<T> operator*(Complex<T> a, Complex<T> b) {
  return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re};
}
template <class T> RT_HD inline T norm(Complex<T> a) { return a.re * a.re + a.im * a.im; }
template <class T> RT_HD inline Complex<T> operator/(Complex<T> a, Complex<T> b) {
  const T scale = T(1) / norm(b);
  return {(a.re * b.re + a.im * b.im) * scale, (a.im * b.re - a.re * b.im) * scale};
}
// The principal square root, from the half-angle formulas; the root of the larger part is
// taken first so that the other part comes from a division, not from a cancellation.
template <class T> RT_HD inline Complex<T> complex_sqrt(Complex<T> z) {
  const T magnitude = square_root(norm(z));
  if (magnitude == T(0)) return {T(0), T(0)};
  const T t1 = square_root(T(0.5) * (magnitude + absolute(z.re)));
  const T t2 = T(0.5) * z.im / t1;
  if (z.re >= T(0)) return {t1, t2};
  return {absolute(t2), z.im < T(0) ? -t1 : t1};
}

// [listing:fresnel_conductor]
// The exact Fresnel reflectance of a conductor of complex index eta + i k (relative to the
// outside), light arriving at cosine cos_i: the dielectric formula with complex numbers.
// The refracted wave's cosine is complex too; |r|^2 replaces r^2.
template <class T> RT_HD inline T fresnel_conductor(T cos_i, T eta, T k) {
  cos_i = clamp_to(cos_i, T(0), T(1));
  const Complex<T> n{eta, k}, c{cos_i, T(0)};
  const Complex<T> sin2_i{T(1) - cos_i * cos_i, T(0)};
  const Complex<T> cos_t = complex_sqrt(Complex<T>{T(1), T(0)} - sin2_i / (n * n));
  const Complex<T> a = n * c;
  const Complex<T> parallel_den = a + cos_t, perpendicular_den = c + n * cos_t;
  // Both denominators vanish only for eta + i k = 1 at grazing incidence, where there is no
  // interface to reflect from.
  if (norm(parallel_den) == T(0) || norm(perpendicular_den) == T(0)) return T(0);
  const T parallel = norm((a - cos_t) / parallel_den);
  const T perpendicular = norm((c - n * cos_t) / perpendicular_den);
  return T(0.5) * (parallel + perpendicular);
}
// [/listing:fresnel_conductor]

RT_HD inline Vec3f fresnel_conductor(float cos_i, Vec3f eta, Vec3f k) {
  return {fresnel_conductor(cos_i, eta.x, k.x), fresnel_conductor(cos_i, eta.y, k.y),
          fresnel_conductor(cos_i, eta.z, k.z)};
}

// ---------------------------------------------------------------------------------------------
// Reflection and refraction about a (micro)normal m; in float for the kernels and in double
// for the quadrature of the compensation tables (energy_compensation.cpp).

template <class T> RT_HD inline Vec3<T> reflect(Vec3<T> wo, Vec3<T> m) {
  return m * (T(2) * dot(wo, m)) - wo;
}

// The direction refracted from wo through the interface with normal m, eta = the index on the
// far side of m over the index on wo's side (m's side when wo.m > 0). False past the critical
// angle: no refracted direction exists.
template <class T> RT_HD inline bool refract(Vec3<T> wo, Vec3<T> m, T eta, Vec3<T>& wt) {
  T cos_i = dot(wo, m);
  if (cos_i < T(0)) {
    eta = T(1) / eta;
    cos_i = -cos_i;
    m = -m;
  }
  const T sin2_t = max_of(T(0), T(1) - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= T(1)) return false;
  const T cos_t = square_root(T(1) - sin2_t);
  wt = -wo / eta + m * (cos_i / eta - cos_t);
  return true;
}

} // namespace rt::ch12
