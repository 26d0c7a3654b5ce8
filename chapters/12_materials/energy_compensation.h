// Chapter 12: the energy a rough metal loses and how it is given back (Kulla and Conty 2017,
// "Revisiting Physically Based Shading at Imageworks"). The GGX model counts light that
// leaves after one bounce off a microfacet; light that bounces twice or more between facets
// is dropped, so a white rough metal looks darker the rougher it is. E(mu, alpha), the share
// that one bounce keeps from a direction of cosine mu, is tabulated once on the host; an extra
// diffuse-like lobe made from it returns the missing 1 - E.
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

// The table as the kernels read it (host or device arrays).
struct CompensationView {
  const float* e;     // E(mu, alpha): k_compensation_size^2, alpha's row by row, mu along a row
  const float* e_avg; // E_avg(alpha) = 2 int E(mu) mu dmu: k_compensation_size
  bool enabled;       // false: no compensation lobe (the energy loss stays visible)
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

// E(mu, alpha) between the nodes by bilinear interpolation in sqrt(mu) and sqrt(alpha).
RT_HD inline float directional_albedo(const CompensationView& table, float mu, float alpha) {
  const TablePosition m = table_position(mu), a = table_position(alpha);
  const float* row = table.e + a.node * k_compensation_size;
  const float* next = row + k_compensation_size;
  const float low = row[m.node] + (row[m.node + 1] - row[m.node]) * m.fraction;
  const float high = next[m.node] + (next[m.node + 1] - next[m.node]) * m.fraction;
  return low + (high - low) * a.fraction;
}

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

// 2 int F(mu) mu dmu of the exact conductor Fresnel term of eta + i k, per channel: the F_avg
// of the compensation lobe's colour (Material::conductor_f_avg).
Vec3f conductor_f_avg(Vec3f eta, Vec3f k);

// The table E(mu, alpha) on the 32 x 32 nodes and E_avg(alpha), on the host; the renderer
// uploads the two arrays for the GPU and points a CompensationView at them.
class CompensationTable {
public:
  // Quadrature points per axis for each node (single_scattering_albedo). Deterministic.
  static constexpr int k_points = 64;
  CompensationTable();
  CompensationView view(bool enabled = true) const {
    return {e_.data(), e_avg_.data(), enabled};
  }
  const std::vector<float>& e() const { return e_; }
  const std::vector<float>& e_avg() const { return e_avg_; }

private:
  std::vector<float> e_, e_avg_;
};

// The mu and alpha of node i: (i / 31)^2.
inline double compensation_node(int i) {
  const double s = double(i) / (k_compensation_size - 1);
  return s * s;
}

} // namespace rt::ch12
