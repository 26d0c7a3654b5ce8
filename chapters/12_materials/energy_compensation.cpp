// Chapter 12: the energy-compensation table and the quadratures it is made by. See
// energy_compensation.h.
#include "energy_compensation.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <thread>
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

// The last few rules asked for, per thread (the glass's quadrature uses two sizes at once).
const Quadrature& cached_gauss_legendre(int n) {
  constexpr int k_kept = 4;
  static thread_local int kept_n[k_kept] = {};
  static thread_local Quadrature kept[k_kept];
  static thread_local int next = 0;
  for (int i = 0; i < k_kept; ++i)
    if (kept_n[i] == n) return kept[i];
  const int slot = next;
  next = (next + 1) % k_kept;
  kept[slot] = gauss_legendre(n);
  kept_n[slot] = n;
  return kept[slot];
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

namespace {

// [listing:dielectric_albedo]
// The glass's E by quadrature over the normals wo sees, in the variables of Dupuy and
// Benyoub's sampler (microfacet.h): stretched to the hemisphere, the view reflected about
// them is uniform on the cap z > -view.z, so E is the plain average over (z, phi) of what a
// microfacet m returns: F G2(wo, wr) / G1(wo) + (1 - F) G2(wo, wt) / G1(wo), the sampler's
// weight for each (Heitz 2014). The integrand has no jumps (G2 fades to 0 at the horizon, 1 - F
// at the critical angle) but it has corners there, and 1 - F rises from the critical angle as
// a square root, as does the visible normal itself at the cap's rim: Gauss-Legendre across
// them converges slowly. So each line of constant phi is cut where one of them lies (each
// found by bisection), and each piece gets its own nodes, crowded towards both its ends by
// z = start + width (3 t^2 - 2 t^3), which turns a square root at either end into a smooth t.
struct LineFeatures {
  Vec3d m;
  double wo_m;
  Vec3d reflected, refracted;
  bool refracts;
};
LineFeatures features_at(Vec3d wo, Vec3d view, double alpha, double eta, double z,
                         double cos_phi, double sin_phi) {
  const double sin_theta = std::sqrt(std::max(0.0, (1.0 - z) * (1.0 + z)));
  const Vec3d cap{sin_theta * cos_phi, sin_theta * sin_phi, z};
  LineFeatures f;
  f.m = unstretched_normal(cap + view, alpha);
  f.wo_m = dot(wo, f.m);
  f.reflected = reflect(wo, f.m);
  f.refracts = f.wo_m > 0.0 && refract(wo, f.m, eta, f.refracted);
  return f;
}

double microfacet_return(Vec3d wo, double alpha, double eta, const LineFeatures& f) {
  if (!(f.wo_m > 0.0)) return 0.0;
  const double fresnel = fresnel_dielectric(f.wo_m, eta);
  double value = 0.0;
  if (f.reflected.z > 0.0) value += fresnel * smith_g2(wo, f.reflected, alpha);
  if (fresnel < 1.0 && f.refracts && f.refracted.z < 0.0)
    value += (1.0 - fresnel) * smith_g2(wo, f.refracted, alpha);
  return value;
}

// The three places on a line where the integrand turns a corner, as signed distances: the
// reflected direction's height, the refracted one's depth, and wo.m over the critical cosine.
struct Corners {
  double value[3];
};
Corners corners_at(Vec3d wo, Vec3d view, double alpha, double eta, double critical, double z,
                   double cos_phi, double sin_phi) {
  const LineFeatures f = features_at(wo, view, alpha, eta, z, cos_phi, sin_phi);
  return {{f.reflected.z, f.refracts ? -f.refracted.z : -1.0, f.wo_m - critical}};
}

} // namespace

double dielectric_albedo(double alpha, double mu, double eta, int points) {
  mu = std::clamp(mu, 1e-6, 1.0);
  const Vec3d wo{std::sqrt((1.0 - mu) * (1.0 + mu)), 0.0, mu};
  const Vec3d view = stretched(wo, alpha);
  const Quadrature& q = cached_gauss_legendre(points);
  // Total internal reflection below this wo.m (none from the thinner side).
  const double critical = eta < 1.0 ? std::sqrt((1.0 - eta) * (1.0 + eta)) : -1.0;
  double sum = 0.0;
  // phi over [0, pi] only: the cap is symmetric about the plane of wo and the normal.
  for (std::size_t a = 0; a < q.nodes.size(); ++a) {
    const double phi = k_pi * q.nodes[a];
    const double cos_phi = std::cos(phi), sin_phi = std::sin(phi);
    const double low = -view.z;
    double cut[5] = {low, 1.0, 1.0, 1.0, 1.0};
    int cuts = 1;
    // At the rim itself the visible normal is 0 / 0: its signs are taken just inside.
    const Corners at_low =
        corners_at(wo, view, alpha, eta, critical, low + 1e-12 * (1.0 - low), cos_phi, sin_phi);
    const Corners at_high = corners_at(wo, view, alpha, eta, critical, 1.0, cos_phi, sin_phi);
    for (int k = 0; k < 3; ++k) {
      if ((at_low.value[k] > 0.0) == (at_high.value[k] > 0.0)) continue;
      double below = low, above = 1.0; // the sign at `below` is at_low's
      for (int step = 0; step < 24; ++step) {
        const double middle = 0.5 * (below + above);
        const Corners c = corners_at(wo, view, alpha, eta, critical, middle, cos_phi, sin_phi);
        ((c.value[k] > 0.0) == (at_low.value[k] > 0.0) ? below : above) = middle;
      }
      // In order as they come: an insertion into the cuts so far.
      int at = cuts++;
      for (; at > 1 && cut[at - 1] > 0.5 * (below + above); --at) cut[at] = cut[at - 1];
      cut[at] = 0.5 * (below + above);
    }
    cut[cuts] = 1.0;
    double line = 0.0;
    // Half the nodes per piece: a piece is smooth, and there are up to four.
    const Quadrature& qz = cached_gauss_legendre(std::max(8, points / 2));
    for (int piece = 0; piece < cuts; ++piece) {
      const double start = cut[piece], width = cut[piece + 1] - start;
      if (!(width > 0.0)) continue;
      for (std::size_t b = 0; b < qz.nodes.size(); ++b) {
        const double t = qz.nodes[b];
        const double z = start + width * t * t * (3.0 - 2.0 * t);
        const double dz = 6.0 * width * t * (1.0 - t);
        line += qz.weights[b] * dz *
                microfacet_return(wo, alpha, eta,
                                  features_at(wo, view, alpha, eta, z, cos_phi, sin_phi));
      }
    }
    sum += q.weights[a] * line / (1.0 + view.z);
  }
  return sum / smith_g1(wo, alpha);
}
// [/listing:dielectric_albedo]

Vec3f conductor_f_avg(Vec3f eta, Vec3f k) {
  const Quadrature& q = cached_gauss_legendre(64);
  double f[3] = {0.0, 0.0, 0.0};
  for (int i = 0; i < 64; ++i)
    for (int channel = 0; channel < 3; ++channel)
      f[channel] += 2.0 * q.weights[i] * q.nodes[i] *
                    fresnel_conductor<double>(q.nodes[i], eta[channel], k[channel]);
  return {float(f[0]), float(f[1]), float(f[2])};
}

namespace {

// [listing:dielectric_table]
// The glass's table, one half per side of the interface, each made on its own thread: some
// 3 seconds on two cores, so once per program, then copied into every CompensationTable.
std::vector<float> make_dielectric_table() {
  std::vector<float> table(k_dielectric_table_size);
  const auto fill_half = [&table](int half) {
    for (int k = 0; k < k_dielectric_eta_nodes; ++k) {
      const double eta = half == 0 ? dielectric_eta_node(k) : 1.0 / dielectric_eta_node(k);
      float* slice = table.data() + (half * k_dielectric_eta_nodes + k) * k_compensation_slice;
      for (int j = 0; j < k_compensation_size; ++j)
        for (int i = 0; i < k_compensation_size; ++i)
          // A smooth interface keeps everything, at every index.
          slice[j * k_compensation_size + i] =
              j == 0 ? 1.0f
                     : float(std::clamp(
                           dielectric_albedo(compensation_node(j), compensation_node(i), eta,
                                             CompensationTable::k_dielectric_points),
                           0.0, 1.0));
    }
  };
  std::thread inside(fill_half, 1);
  fill_half(0);
  inside.join();
  return table;
}
// [/listing:dielectric_table]

const std::vector<float>& dielectric_table() {
  static const std::vector<float> table = make_dielectric_table();
  return table;
}

} // namespace

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
  dielectric_ = dielectric_table();
}
// [/listing:compensation_table]

} // namespace rt::ch12
