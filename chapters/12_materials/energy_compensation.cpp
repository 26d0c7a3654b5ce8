// Chapter 12: the energy-compensation table and the quadratures it is made by. See
// energy_compensation.h.
#include "energy_compensation.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace rt::ch12 {

namespace {

constexpr double k_pi = std::numbers::pi;

// The nodes and weights of n-point Gauss-Legendre quadrature on [0, 1]: Newton's method on
// the Legendre polynomial from the Chebyshev guess, as every numerical recipe does it.
struct Quadrature {
  std::vector<double> nodes, weights;
};
Quadrature gauss_legendre(int n) {
  Quadrature q{std::vector<double>(n), std::vector<double>(n)};
  for (int i = 0; i < n; ++i) {
    double x = std::cos(k_pi * (i + 0.75) / (n + 0.5)), derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x; // P_0 and P_1, then up the three-term recurrence
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-15) break;
    }
    q.nodes[i] = 0.5 * (1.0 - x);
    q.weights[i] = 1.0 / ((1.0 - x * x) * derivative * derivative); // 2 / (...) halved
  }
  return q;
}

const Quadrature& cached_gauss_legendre(int n) {
  static thread_local int cached_n = 0;
  static thread_local Quadrature cached;
  if (cached_n != n) {
    cached = gauss_legendre(n);
    cached_n = n;
  }
  return cached;
}

// [listing:single_scattering_albedo]
// The inner integral, over xi in [0, xi_cut] at one azimuth phi of the half vector. Near the
// cut the integrand turns from its value to 0 in a layer as thin as mu / alpha; xi = xi_cut
// (1 - (1 - t)^3) crowds the nodes there.
double albedo_at_azimuth(const Quadrature& q, Vec3d wo, double alpha, double phi) {
  const double mu = wo.z, alpha2 = alpha * alpha;
  const double cos_phi = std::cos(phi), sin_phi = std::sin(phi);
  // The reflected direction's z is 2 (wo.h) h.z - mu = R cos(2 theta_h - delta): it stays
  // above the horizon for theta_h below theta_cut, the one zero of that cosine.
  const double delta = std::atan2(wo.x * cos_phi, mu);
  const double theta_cut = 0.5 * (delta + 0.5 * k_pi);
  const double s = std::sin(theta_cut), c = std::cos(theta_cut);
  const double xi_cut = s * s / (alpha2 * c * c + s * s);
  double sum = 0.0;
  for (std::size_t b = 0; b < q.nodes.size(); ++b) {
    const double t = 1.0 - q.nodes[b];
    const double xi = xi_cut * (1.0 - t * t * t);
    const double dxi = 3.0 * xi_cut * t * t;
    // tan^2(theta_h) = alpha^2 xi / (1 - xi), written without the tangent.
    const double scale = 1.0 - xi + alpha2 * xi;
    const double cos_h = std::sqrt((1.0 - xi) / scale);
    const double sin_h = std::sqrt(alpha2 * xi / scale);
    const Vec3d h{sin_h * cos_phi, sin_h * sin_phi, cos_h};
    const double wo_h = dot(wo, h);
    const Vec3d wi = h * (2.0 * wo_h) - wo;
    if (!(wi.z > 0.0) || !(wo_h > 0.0) || !(cos_h > 0.0)) continue;
    // f cos / (D(h) cos theta_h dh) for F = 1: D G2 / (4 mu) times dwi / dh = 4 wo.h.
    sum += q.weights[b] * dxi * smith_g2(wo, wi, alpha) * wo_h / (mu * cos_h);
  }
  return sum;
}

} // namespace

double single_scattering_albedo(double alpha, double mu, int points) {
  mu = std::clamp(mu, 1e-6, 1.0);
  const Vec3d wo{std::sqrt((1.0 - mu) * (1.0 + mu)), 0.0, mu};
  const Quadrature& q = cached_gauss_legendre(points);
  // phi over [0, pi] only (the lobe is symmetric about the plane of wo and the normal), in
  // two halves whose nodes crowd towards phi = pi / 2, where the cut moves fastest at grazing
  // wo. D(h) cos(theta_h) dh = dxi dphi / (2 pi).
  double sum = 0.0;
  for (std::size_t a = 0; a < q.nodes.size(); ++a) {
    const double t = q.nodes[a], dphi = 1.5 * k_pi * t * t;
    sum += q.weights[a] * dphi *
           (albedo_at_azimuth(q, wo, alpha, 0.5 * k_pi * (1.0 - t * t * t)) +
            albedo_at_azimuth(q, wo, alpha, 0.5 * k_pi * (1.0 + t * t * t)));
  }
  return sum / k_pi;
}
// [/listing:single_scattering_albedo]

Vec3f conductor_f_avg(Vec3f eta, Vec3f k) {
  const Quadrature& q = cached_gauss_legendre(64);
  double f[3] = {0.0, 0.0, 0.0};
  for (int i = 0; i < 64; ++i)
    for (int channel = 0; channel < 3; ++channel)
      f[channel] += 2.0 * q.weights[i] * q.nodes[i] *
                    fresnel_conductor<double>(q.nodes[i], eta[channel], k[channel]);
  return {float(f[0]), float(f[1]), float(f[2])};
}

// [listing:compensation_table]
// E on the nodes, then E_avg from the table itself. Between two nodes E is linear in s =
// sqrt(mu), so 2 int E mu dmu = 4 int E s^3 ds is a polynomial integral, summed exactly.
// Made so, the compensation lobe gives back exactly 1 - E of the table, whatever the
// table's own error; the furnace then measures only that error.
CompensationTable::CompensationTable()
    : e_(k_compensation_size * k_compensation_size), e_avg_(k_compensation_size) {
  const auto node_s = [](int i) { return double(i) / (k_compensation_size - 1); };
  for (int j = 0; j < k_compensation_size; ++j) {
    const double alpha = compensation_node(j);
    double average = 0.0, previous = 0.0;
    for (int i = 0; i < k_compensation_size; ++i) {
      // A smooth mirror keeps everything; one bounce loses nothing from alpha = 0.
      const float stored =
          j == 0
              ? 1.0f
              : float(std::clamp(
                    single_scattering_albedo(alpha, compensation_node(i), k_points), 0.0, 1.0));
      e_[j * k_compensation_size + i] = stored;
      const double e = stored; // the average of what the kernels will read
      if (i > 0) {
        const double a = node_s(i - 1), b = node_s(i), width = b - a;
        const double a4 = a * a * a * a, b4 = b * b * b * b;
        const double s4 = (b4 - a4) / 4.0, s5 = (b4 * b - a4 * a) / 5.0;
        // int (b - s) s^3 ds and int (s - a) s^3 ds over [a, b], the weights of E_a and E_b.
        average += 4.0 / width * (previous * (b * s4 - s5) + e * (s5 - a * s4));
      }
      previous = e;
    }
    e_avg_[j] = float(average);
  }
}
// [/listing:compensation_table]

} // namespace rt::ch12
