// Chapter 12: the energy a rough metal loses and how it is given back (Kulla and Conty 2017,
// "Revisiting Physically Based Shading at Imageworks"). The GGX model counts light that
// leaves after one bounce off a microfacet; light that bounces twice or more between facets
// is dropped, so a white rough metal looks darker the rougher it is. E(mu, alpha), the share
// that one bounce keeps from a direction of cosine mu, is tabulated once on the host; an extra
// diffuse-like lobe made from it returns the missing 1 - E. Rough glass loses light the same
// way; its lobes are scaled up by 1 / E of the interface instead (Turquin 2019), from a
// second table over the index of refraction as well.
#pragma once

#include <vector>

#include "microfacet.h"
#include "rt/hd.h"
#include "rt/vec.h"

namespace rt::ch12 {

// The table's nodes per axis: mu = cos(theta_o) = (i / 31)^2 and alpha = (j / 31)^2, both from
// 0 to 1. One bounce loses most at mu close to alpha (a narrow lobe at grazing incidence is
// cut by the horizon: E dips to 0.89 there for every small alpha), so the nodes are spaced
// evenly in sqrt(mu) and sqrt(alpha) (the roughness): the dip runs along the table's diagonal
// down to alpha = 0.001, where nodes spaced evenly in mu and alpha would miss it.
inline constexpr int k_compensation_size = 32;

// The glass's table: E(mu, alpha, eta) of a rough dielectric interface, reflection and
// refraction together, for light arriving from the side of index n_o at an interface whose
// far side has index n_t, eta = n_t / n_o. Two halves: eta from 1 to k_dielectric_max_eta
// (light arriving from outside glass) and 1 / eta over the same nodes (from inside, where
// total internal reflection starts at sin theta = 1 / eta). In each half a 32 x 32 slice of
// mu and alpha, as the metal's table, per node of eta, the nodes spaced evenly in 1 / eta:
// (1 - 1 / eta) / (1 - 1 / max) = k / 15. E bends less along 1 / eta than along eta (linear
// interpolation between the nodes errs by at most 2e-3 where spacing in eta errs by 1e-2).
// 2 x 16 x 32 x 32 floats: 128 KiB.
inline constexpr int k_dielectric_eta_nodes = 16;
inline constexpr float k_dielectric_max_eta = 3.0f;
inline constexpr int k_compensation_slice = k_compensation_size * k_compensation_size;
inline constexpr int k_dielectric_table_size =
    2 * k_dielectric_eta_nodes * k_compensation_slice;

// The table as the kernels read it (host or device arrays).
struct CompensationView {
  const float* e;          // E(mu, alpha): k_compensation_slice, alpha's row by row, mu along
  const float* e_avg;      // E_avg(alpha) = 2 int E(mu) mu dmu: k_compensation_size
  const float* dielectric; // E(mu, alpha, eta) of glass: k_dielectric_table_size (above)
  bool enabled;            // false: no compensation (the energy loss stays visible)
};

// The node below x in [0, 1] and the fraction of the way to the next one, in sqrt(x).
struct TablePosition {
  int node;
  float fraction;
};
RT_HD inline TablePosition table_position(float x) {
  const float position = square_root(clamp_to(x, 0.0f, 1.0f)) * float(k_compensation_size - 1);
  const int node = min_of(int(position), k_compensation_size - 2);
  return {node, position - float(node)};
}

// A slice E(mu, alpha) between the nodes by bilinear interpolation in sqrt(mu) and
// sqrt(alpha).
RT_HD inline float slice_value(const float* slice, float mu, float alpha) {
  const TablePosition m = table_position(mu), a = table_position(alpha);
  const float* row = slice + a.node * k_compensation_size;
  const float* next = row + k_compensation_size;
  const float low = row[m.node] + (row[m.node + 1] - row[m.node]) * m.fraction;
  const float high = next[m.node] + (next[m.node + 1] - next[m.node]) * m.fraction;
  return low + (high - low) * a.fraction;
}
RT_HD inline float directional_albedo(const CompensationView& table, float mu, float alpha) {
  return slice_value(table.e, mu, alpha);
}

// [listing:dielectric_albedo_lookup]
// E(mu, alpha, eta) of the glass: the half for eta's side of 1, the two slices about eta (or
// 1 / eta) and linear interpolation between them in 1 / eta. An eta past the last node reads
// the last.
RT_HD inline float dielectric_directional_albedo(const CompensationView& table, float mu,
                                                 float alpha, float eta) {
  const int half = eta < 1.0f ? 1 : 0;
  const float inverse = eta < 1.0f ? eta : 1.0f / eta; // 1 / eta of the half, in (0, 1]
  const float position =
      clamp_to((1.0f - inverse) / (1.0f - 1.0f / k_dielectric_max_eta), 0.0f, 1.0f) *
      float(k_dielectric_eta_nodes - 1);
  const int node = min_of(int(position), k_dielectric_eta_nodes - 2);
  const float fraction = position - float(node);
  const float* slice =
      table.dielectric + (half * k_dielectric_eta_nodes + node) * k_compensation_slice;
  const float low = slice_value(slice, mu, alpha);
  const float high = slice_value(slice + k_compensation_slice, mu, alpha);
  return low + (high - low) * fraction;
}
// [/listing:dielectric_albedo_lookup]

// E_avg(alpha) between the nodes, linearly in sqrt(alpha): it is then exactly 2 int E(mu) mu
// dmu of the interpolated E, so the compensation lobe returns exactly 1 - E (see the table's
// construction).
RT_HD inline float average_albedo(const CompensationView& table, float alpha) {
  const TablePosition a = table_position(alpha);
  return table.e_avg[a.node] + (table.e_avg[a.node + 1] - table.e_avg[a.node]) * a.fraction;
}

// Below this 1 - E_avg a surface loses nothing worth giving back (a nearly smooth metal), and
// the lobe, a ratio of two vanishing terms, is left out.
inline constexpr float k_min_lost_energy = 1e-6f;

// [listing:compensation_lobe]
// The white compensation lobe times cos(theta_i): f_ms = (1 - E(mu_o)) (1 - E(mu_i)) /
// (pi (1 - E_avg)). Integrated over wi it gives 1 - E(mu_o), what one bounce lost from wo,
// and it is symmetric in wo and wi, as a BRDF must be.
RT_HD inline float compensation_lobe(const CompensationView& table, float mu_o, float mu_i,
                                     float alpha) {
  if (!(mu_o > 0.0f) || !(mu_i > 0.0f)) return 0.0f;
  const float lost = 1.0f - average_albedo(table, alpha);
  if (!(lost > k_min_lost_energy)) return 0.0f;
  const float lost_o = 1.0f - directional_albedo(table, mu_o, alpha);
  const float lost_i = 1.0f - directional_albedo(table, mu_i, alpha);
  return lost_o * lost_i / (k_pi_of<float> * lost) * mu_i;
}

// The colour of the returned light for a Fresnel term whose cosine-weighted mean is f_avg:
// each further bounce keeps f_avg of what reaches it, the series sums to F_avg^2 E_avg /
// (1 - F_avg (1 - E_avg)). White (f_avg = 1) gives 1.
RT_HD inline Vec3f compensation_colour(Vec3f f_avg, float e_avg) {
  const auto channel = [e_avg](float f) { return f * f * e_avg / (1.0f - f * (1.0f - e_avg)); };
  return {channel(f_avg.x), channel(f_avg.y), channel(f_avg.z)};
}
// [/listing:compensation_lobe]

// Schlick's F_avg: 2 int (F0 + (1 - F0)(1 - mu)^5) mu dmu = F0 + (1 - F0) / 21.
RT_HD inline Vec3f schlick_f_avg(Vec3f f0) {
  return f0 + (Vec3f{1.0f, 1.0f, 1.0f} - f0) * (1.0f / 21.0f);
}

} // namespace rt::ch12

namespace rt::ch12 {

// E(mu, alpha) of a white (F = 1) GGX conductor, one bounce, in double precision: the
// integral over the half vector h, in the variable xi = tan^2 / (alpha^2 + tan^2) in which
// D(h) cos(theta_h) dh is uniform, split where the reflected direction crosses the horizon
// (where that is has a closed form), by Gauss-Legendre quadrature with `points` nodes on
// each axis. With the default it agrees with itself at twice the nodes to ~1e-9 (the tests
// measure it). mu is taken as at least 1e-6.
double single_scattering_albedo(double alpha, double mu, int points = 128);

// E(mu, alpha, eta) of a rough dielectric interface (white, no absorption), one scattering
// off the microfacets, reflection and refraction together, for light from the side of index
// n_o, eta = n_t / n_o; refraction's radiance factor (n_o / n_t)^2 left out, as energy
// counts it. Gauss-Legendre quadrature over the visible normals in double with `points`
// nodes on each axis (energy_compensation.cpp says how). mu is taken as at least 1e-6.
double dielectric_albedo(double alpha, double mu, double eta, int points = 64);

// 2 int F(mu) mu dmu of the exact conductor Fresnel term of eta + i k, per channel: the F_avg
// of the compensation lobe's colour (Material::conductor_f_avg).
Vec3f conductor_f_avg(Vec3f eta, Vec3f k);

// The table E(mu, alpha) on the 32 x 32 nodes, E_avg(alpha) and the glass's E(mu, alpha, eta),
// on the host; the renderer uploads the three arrays for the GPU and points a
// CompensationView at them.
class CompensationTable {
public:
  // Quadrature points per axis for each node (single_scattering_albedo, dielectric_albedo).
  // Deterministic.
  static constexpr int k_points = 64;
  static constexpr int k_dielectric_points = 32;
  CompensationTable();
  CompensationView view(bool enabled = true) const {
    return {e_.data(), e_avg_.data(), dielectric_.data(), enabled};
  }
  const std::vector<float>& e() const { return e_; }
  const std::vector<float>& e_avg() const { return e_avg_; }
  const std::vector<float>& dielectric() const { return dielectric_; }

private:
  std::vector<float> e_, e_avg_, dielectric_;
};

// The mu and alpha of node i: (i / 31)^2.
inline double compensation_node(int i) {
  const double s = double(i) / (k_compensation_size - 1);
  return s * s;
}
// The eta of the glass table's node k (its second half holds 1 / that).
inline double dielectric_eta_node(int k) {
  return 1.0 / (1.0 - (1.0 - 1.0 / k_dielectric_max_eta) * k / (k_dielectric_eta_nodes - 1));
}

} // namespace rt::ch12
