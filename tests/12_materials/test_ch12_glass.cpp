// Chapter 12 tests of rough glass that keeps its energy (Turquin's scaling by the table of
// E(mu, alpha, eta), energy_compensation.h and bsdf.h): the table's quadrature against a closed
// form, against itself at many more nodes and against brute-force Monte Carlo of the sampler;
// one scattering event, which with the scale returns all the light from every direction and
// without it returns E; the price in reciprocity, exactly E(wi) / E(wo); and the white furnace
// of a rough glass sphere at every roughness, invisible with the scale, and without it as dark
// as a walk of one-scattering events through a sphere predicts; on the GPU as on the CPU.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "rt_catch.h"

#include "bsdf.h"
#include "energy_compensation.h"
#include "gpu_guard.h"
#include "material_cases.h"

using namespace rt;
using namespace rt::ch12;
using namespace rt::ch12::testing;

namespace {

constexpr double k_pi = std::numbers::pi;

const CompensationTable& table() {
  static const CompensationTable made;
  return made;
}

Bsdf glass(float alpha, float ior) {
  return {MaterialModel::metallic_roughness, {1, 1, 1}, 0, alpha, ior, 1, {}, {}, {}};
}

// A direction at theta degrees from the normal, on the outside (side 1) or inside (side -1).
Vec3f direction_at(double theta_degrees, float side) {
  const double theta = theta_degrees * k_pi / 180.0;
  return {float(std::sin(theta)), 0.0f, side * float(std::cos(theta))};
}

// Uniform numbers in [0, 1) from a seeded generator: 24 bits, so never 1.
struct Numbers {
  std::mt19937 generator;
  explicit Numbers(unsigned seed) : generator(seed) {}
  float next() { return float(generator() >> 8) * (1.0f / 16777216.0f); }
};

// The mean of the sampled weights from wo (one scattering event under a white sky), its
// standard error, the share of the weight that came through the interface rather than back,
// and the raw energy: the weights without refraction's radiance factor (n_o / n_i)^2, what E
// counts.
struct EventMean {
  double mean = 0.0, error = 0.0, energy = 0.0, energy_error = 0.0;
};
EventMean one_event(const Bsdf& b, Vec3f wo, const CompensationView& view, int samples,
                    unsigned seed) {
  Numbers numbers(seed);
  double sum = 0.0, square = 0.0, energy = 0.0, energy_square = 0.0;
  for (int i = 0; i < samples; ++i) {
    // Stratified in the lobe choice's number, as the metal's furnace is in u.
    const float u_lobe = (float(i) + numbers.next()) / float(samples);
    BsdfSample s;
    if (!bsdf_sample(b, wo, u_lobe, numbers.next(), numbers.next(), view, s)) continue;
    const double w = s.weight.x;
    double raw = w;
    if (s.wi.z * wo.z < 0.0f) { // refracted: undo the factor 1 / eta'^2
      const double eta = wo.z > 0.0f ? b.ior : 1.0 / b.ior;
      raw = w * eta * eta;
    }
    sum += w;
    square += w * w;
    energy += raw;
    energy_square += raw * raw;
  }
  const double n = samples;
  EventMean m;
  m.mean = sum / n;
  m.error = std::sqrt(std::max(0.0, square / n - m.mean * m.mean) / n);
  m.energy = energy / n;
  m.energy_error = std::sqrt(std::max(0.0, energy_square / n - m.energy * m.energy) / n);
  return m;
}

} // namespace

TEST_CASE("the glass's table: its quadrature meets the closed form at eta 1, converges, and "
          "its nodes agree with brute-force sampling",
          "[glass]") {
  // At eta 1 every microfacet sends wo straight on to -wo, and E is G2(wo, -wo) / G1(wo) =
  // (1 + Lambda) / (1 + 2 Lambda): a closed form at every roughness and angle ((1 + mu) / 2 at
  // alpha 1).
  double worst_closed_form = 0.0;
  for (const double alpha : {0.001, 0.01, 0.3, 1.0})
    for (const double mu : {1e-4, 0.01, 0.3, 0.8, 1.0}) {
      const Vec3d wo{std::sqrt(1.0 - mu * mu), 0.0, mu};
      const double lambda = smith_lambda(wo, alpha);
      worst_closed_form =
          std::max(worst_closed_form, std::abs(dielectric_albedo(alpha, mu, 1.0) -
                                               (1.0 + lambda) / (1.0 + 2.0 * lambda)));
    }
  INFO("worst difference from the closed form at eta 1: " << worst_closed_form);
  CHECK(worst_closed_form < 1e-9);

  // The table's nodes per axis against twelve times as many, outside and inside the glass.
  constexpr int k_points = CompensationTable::k_dielectric_points;
  double worst_outside = 0.0, worst_inside = 0.0;
  for (const double alpha : {0.01, 0.0625, 0.25, 0.5625, 1.0})
    for (const double mu : {0.01, 0.1, 0.5, 0.9, 1.0})
      for (const double eta : {1.5, 2.4}) {
        worst_outside =
            std::max(worst_outside, std::abs(dielectric_albedo(alpha, mu, eta, k_points) -
                                             dielectric_albedo(alpha, mu, eta, 384)));
        worst_inside =
            std::max(worst_inside, std::abs(dielectric_albedo(alpha, mu, 1.0 / eta, k_points) -
                                            dielectric_albedo(alpha, mu, 1.0 / eta, 384)));
      }
  INFO("the table's " << k_points << " nodes against 384: outside " << worst_outside
                      << ", inside " << worst_inside);
  CHECK(worst_outside < 2e-4);
  CHECK(worst_inside < 3e-3);

  // The table's nodes against the sampler itself (float, compensation off), many samples:
  // the raw energy of one event, which is what E is.
  const CompensationView plain = table().view(false);
  unsigned seed = 100;
  for (const int j : {5, 16, 31})        // alpha 0.026, 0.27, 1
    for (const int i : {8, 20, 31})      // mu 0.067, 0.42, 1
      for (const int k : {0, 4, 11, 15}) // eta 1, 1.53, 2.47, 3
        for (const int half : {0, 1}) {
          // From inside, an index just above 1 already reflects totally off the facets it
          // meets at grazing angles, which the node at exactly 1 does not: the inside half's
          // first interval is the table's least accurate (0.4% at alpha 0.026, mu 0.067).
          if (half == 1 && k == 0) continue;
          const double mu = compensation_node(i);
          const float stored =
              table().dielectric()[((half * k_dielectric_eta_nodes + k) * k_compensation_size +
                                    j) *
                                       k_compensation_size +
                                   i];
          // An interface of index exactly 1 is a delta lobe in the BSDF: its node holds the
          // limit eta -> 1, sampled just above 1.
          const Bsdf b = glass(float(compensation_node(j)),
                               float(k == 0 ? 1.0001 : dielectric_eta_node(k)));
          const Vec3f wo{float(std::sqrt(1.0 - mu * mu)), 0.0f, float(half == 0 ? mu : -mu)};
          const EventMean m = one_event(b, wo, plain, 40000, seed++);
          CAPTURE(j, i, k, half, stored, m.energy, m.energy_error);
          CHECK(std::abs(m.energy - stored) < 4.0 * m.energy_error + 2e-3);
          CHECK(stored <= 1.0f);
          CHECK(stored > 0.2f);
        }
}

TEST_CASE("one scattering event off rough glass keeps all the light with the scale, and E "
          "without it, from outside and inside",
          "[glass]") {
  constexpr int k_samples = 40000;
  for (const float ior : {1.5f, 2.4f})
    for (const float roughness : {0.1f, 0.25f, 0.5f, 0.75f, 1.0f})
      for (const float side : {1.0f, -1.0f})
        for (const double theta : {0.0, 30.0, 60.0, 85.0}) {
          const Bsdf b = glass(roughness * roughness, ior);
          const Vec3f wo = direction_at(theta, side);
          const float eta = side > 0.0f ? ior : 1.0f / ior;
          const double expected = dielectric_albedo(b.alpha, std::abs(wo.z), eta, 384);
          const EventMean plain = one_event(b, wo, table().view(false), k_samples, 200);
          const EventMean kept = one_event(b, wo, table().view(true), k_samples, 200);
          CAPTURE(ior, roughness, side, theta, expected, plain.energy, plain.energy_error,
                  kept.energy, kept.energy_error);
          // Without the scale, one event keeps E(mu, alpha, eta); with it, everything, up to
          // the table's interpolation (the same numbers drive both, so the ratio is exact
          // but for the lookup).
          CHECK(std::abs(plain.energy - expected) < 4.0 * plain.energy_error + 1e-3);
          CHECK(std::abs(kept.energy - 1.0) < 4.0 * kept.energy_error + 3e-3);
          CHECK(kept.energy / plain.energy ==
                Approx(1.0 / dielectric_directional_albedo(table().view(true), std::abs(wo.z),
                                                           b.alpha, eta))
                    .epsilon(1e-4));
        }
}

TEST_CASE("a wrong scale, E read for the other side of the interface, is caught by the "
          "one-event furnace",
          "[glass]") {
  // The wrong twin: the lobe scaled by 1 / E of the opposite side (eta and 1 / eta swapped).
  // Seen from inside, where total internal reflection makes E small, it returns far too
  // little; the same test that passes the right scale must fail it.
  const Bsdf b = glass(0.5f, 1.5f);
  const Vec3f wo = direction_at(0.0, -1.0f);
  const CompensationView view = table().view(true);
  const EventMean right = one_event(b, wo, view, 40000, 300);
  const float own = dielectric_directional_albedo(view, 1.0f, b.alpha, 1.0f / 1.5f);
  const float other = dielectric_directional_albedo(view, 1.0f, b.alpha, 1.5f);
  const double wrong = right.energy * own / other;
  CAPTURE(right.energy, right.energy_error, wrong, own, other);
  CHECK(std::abs(right.energy - 1.0) < 4.0 * right.energy_error + 3e-3);
  CHECK(std::abs(wrong - 1.0) > 4.0 * right.energy_error + 3e-3);
}

TEST_CASE("the scaled glass keeps the sampler's weight f cos / pdf and loses reciprocity by "
          "exactly E(wi) / E(wo)",
          "[glass]") {
  const CompensationView view = table().view(true), plain = table().view(false);
  double worst_weight = 0.0, worst_ratio = 0.0;
  int refractions = 0, reflections = 0;
  Numbers numbers(400);
  for (const float ior : {1.5f, 2.4f})
    for (const float alpha : {0.05f, 0.3f, 1.0f})
      for (int n = 0; n < 2000; ++n) {
        const Bsdf b = glass(alpha, ior);
        const float side = n % 2 ? -1.0f : 1.0f;
        const float cosine = 0.05f + 0.9f * numbers.next();
        const Vec3f wo{std::sqrt(1.0f - cosine * cosine), 0.0f, side * cosine};
        BsdfSample s;
        if (!bsdf_sample(b, wo, numbers.next(), numbers.next(), numbers.next(), view, s))
          continue;
        const Vec3f expected = bsdf_eval(b, wo, s.wi, view) / bsdf_pdf(b, wo, s.wi, view);
        worst_weight =
            std::max(worst_weight, std::abs(double(s.weight.x - expected.x)) / expected.x);
        if (std::abs(s.wi.z) < 0.05f) continue;
        // f_c(wo, wi) = f(wo, wi) / E(wo): against the unscaled BSDF's reciprocity, the
        // forward and backward values differ by E(wi) / E(wo).
        const auto kept = [&](Vec3f w) {
          return dielectric_directional_albedo(view, std::abs(w.z), alpha,
                                               w.z > 0.0f ? ior : 1.0f / ior);
        };
        const double forward = bsdf_eval(b, wo, s.wi, view).x / std::abs(s.wi.z);
        const double backward = bsdf_eval(b, s.wi, wo, view).x / std::abs(wo.z);
        const double forward_plain = bsdf_eval(b, wo, s.wi, plain).x / std::abs(s.wi.z);
        const double backward_plain = bsdf_eval(b, s.wi, wo, plain).x / std::abs(wo.z);
        if (!(forward_plain > 0.0) || !(backward_plain > 0.0)) continue;
        const double ratio = (forward / backward) / (forward_plain / backward_plain);
        worst_ratio = std::max(worst_ratio, std::abs(ratio / (kept(s.wi) / kept(wo)) - 1.0));
        (s.wi.z * wo.z > 0.0f ? reflections : refractions) += 1;
      }
  INFO("worst relative differences: weight " << worst_weight << ", the ratio " << worst_ratio);
  CHECK(reflections > 1000);
  CHECK(refractions > 1000);
  CHECK(worst_weight < 1e-5);
  CHECK(worst_ratio < 1e-4);
}

TEST_CASE("the scale is finite at grazing cos 1e-6, alpha 1e-4, indices 1 to 4 and below 1",
          "[glass]") {
  const CompensationView view = table().view(true);
  int bad = 0, evaluations = 0;
  for (const float alpha : {1e-6f, 1e-4f, 0.01f, 1.0f})
    for (const float ior : {1.0f, 1.0001f, 1.5f, 2.4f, 4.0f, 0.7f})
      for (const float c : {1.0f, 1e-3f, 1e-6f, 0.0f, -1e-6f, -1e-3f, -1.0f}) {
        const Vec3f wo{std::sqrt(std::max(0.0f, 1.0f - c * c)), 0.0f, c};
        const float scale = dielectric_compensation(glass(alpha, ior), wo, view);
        bad += std::isfinite(scale) && scale >= 1.0f && scale < 10.0f ? 0 : 1;
        ++evaluations;
      }
  INFO(bad << " of " << evaluations << " scales not finite or not in [1, 10)");
  CHECK(bad == 0);
  // No scale where nothing is lost: a smooth interface, or compensation switched off.
  CHECK(dielectric_compensation(glass(0.0f, 1.5f), direction_at(60, 1), view) == 1.0f);
  CHECK(dielectric_compensation(glass(0.5f, 1.5f), direction_at(60, 1), table().view(false)) ==
        1.0f);
}

// ---------------------------------------------------------------------------------------------
// The white furnace of a rough glass sphere.

namespace {

const Extent k_furnace_extent{32, 24};

MeanAndError glass_furnace(float roughness, float ior, bool compensation,
                           const CameraSpec& camera, int samples, unsigned long long& bad) {
  Material m = named_material("rough-glass", roughness);
  m.ior = ior;
  const MaterialScene scene = make_sphere_in_sky(m, 4, 1.0f);
  const Render r = render(scene, Backend::cpu, camera, k_furnace_extent, samples, {},
                          {.compensation = compensation});
  bad = r.non_finite;
  return pixel_statistics(r.mean);
}

// What the uncompensated sphere returns to a ray that meets it head-on, predicted without the
// renderer: a walk of one-scattering events (the BSDF's sampler alone), using that a chord of a
// sphere meets the surface at the same angle at both ends. A reflection outside, or a
// refraction out from inside, leaves under the sky; anything else meets the inside again at
// the cosine it left with. The mean and its standard error over `paths` walks; with the
// scale on, the same walk says what the scaled sphere returns: 1 if the table is right.
MeanAndError sphere_walk(const Bsdf& b, bool compensation, int paths, unsigned seed) {
  Numbers numbers(seed);
  const CompensationView view = table().view(compensation);
  double sum = 0.0, square = 0.0;
  for (int p = 0; p < paths; ++p) {
    Vec3f wo{0.0f, 0.0f, 1.0f};
    double throughput = 1.0, value = 0.0;
    for (int event = 0; event < 10000 && throughput > 0.0; ++event) {
      BsdfSample s;
      if (!bsdf_sample(b, wo, numbers.next(), numbers.next(), numbers.next(), view, s)) break;
      throughput *= s.weight.x;
      const bool outside = wo.z > 0.0f, stays = s.wi.z * wo.z > 0.0f;
      if (outside == stays) { // reflected outside, or refracted out of the sphere
        value = throughput;
        break;
      }
      const float c = std::min(std::abs(s.wi.z), 1.0f);
      wo = {std::sqrt((1.0f - c) * (1.0f + c)), 0.0f, -c};
      // Russian roulette on what is left: inside, the throughput is the energy over eta^2.
      const double energy = throughput * b.ior * b.ior;
      if (event > 8 && energy < 0.5) {
        if (numbers.next() >= energy * 2.0) break;
        throughput /= energy * 2.0;
      }
    }
    sum += value;
    square += value * value;
  }
  const double mean = sum / paths;
  return {mean, std::sqrt(std::max(0.0, square / paths - mean * mean) / paths)};
}

} // namespace

TEST_CASE("furnace: rough glass spheres of every roughness are invisible with the scale, and "
          "without it lose what one-scattering walks predict",
          "[glass][ch12]") {
  for (const float ior : {1.5f, 2.4f})
    for (const float roughness : {0.1f, 0.25f, 0.5f, 0.75f, 1.0f}) {
      CAPTURE(ior, roughness);
      unsigned long long bad = 1;
      const MeanAndError kept = glass_furnace(roughness, ior, true, sphere_camera(), 64, bad);
      CAPTURE(kept.mean, kept.standard_error);
      CHECK(bad == 0);
      // Within 0.5%, or within the image's noise where that is larger: with E as low as 0.3
      // inside rough glass of index 2.4, a path's weights (1 / E each, 1 on average) multiply
      // over many internal reflections, and 64 samples per pixel leave a standard error of a
      // few percent. The walk below, free of the renderer's roulette, pins the mean.
      CHECK(std::abs(kept.mean - 1.0) < 0.005 + 4.0 * kept.standard_error);
      // Head-on (the camera narrowed to the sphere's middle), without the scale: the image's
      // mean against the walk's prediction, within both noises and a little for the facets of
      // the tessellated sphere.
      const MeanAndError lost =
          glass_furnace(roughness, ior, false, sphere_centre_camera(), 32, bad);
      const MeanAndError walk =
          sphere_walk(glass(roughness * roughness, ior), false, 100000, 500);
      const MeanAndError walk_kept =
          sphere_walk(glass(roughness * roughness, ior), true, 100000, 600);
      CAPTURE(walk_kept.mean, walk_kept.standard_error);
      CHECK(std::abs(walk_kept.mean - 1.0) < 0.005 + 4.0 * walk_kept.standard_error);
      CAPTURE(lost.mean, lost.standard_error, walk.mean, walk.standard_error);
      CHECK(bad == 0);
      CHECK(std::abs(lost.mean - walk.mean) <
            4.0 * std::hypot(lost.standard_error, walk.standard_error) + 0.005);
      if (roughness >= 0.5f) CHECK(lost.mean < 0.99); // a loss to see
    }
}

TEST_CASE("GPU: the rough glass spheres are invisible there too, and lose what the CPU's lose "
          "without the scale",
          "[glass][gpu]") {
  // The table is made on the host and read by both backends alike; the images agree within
  // their noise (a path can turn another way where the GPU's maths library rounds an ulp
  // apart, as test_ch12_gpu.cpp says).
  RT_REQUIRE_GPU();
  for (const float ior : {1.5f, 2.4f})
    for (const float roughness : {0.5f, 1.0f})
      for (const bool compensation : {true, false}) {
        CAPTURE(ior, roughness, compensation);
        Material m = named_material("rough-glass", roughness);
        m.ior = ior;
        const MaterialScene scene = make_sphere_in_sky(m, 4, 1.0f);
        const MaterialOptions options{.compensation = compensation};
        const Render cpu =
            render(scene, Backend::cpu, sphere_camera(), k_furnace_extent, 64, {}, options);
        const Render gpu =
            render(scene, Backend::gpu, sphere_camera(), k_furnace_extent, 64, {}, options);
        CHECK(gpu.non_finite == 0);
        const MeanAndError c = pixel_statistics(cpu.mean), g = pixel_statistics(gpu.mean);
        CAPTURE(c.mean, c.standard_error, g.mean, g.standard_error);
        CHECK(std::abs(c.mean - g.mean) <
              4.0 * std::hypot(c.standard_error, g.standard_error) + 0.005);
        if (compensation) CHECK(std::abs(g.mean - 1.0) < 0.005 + 4.0 * g.standard_error);
      }
}
