// Chapter 12: the chi-square test of a BSDF's sampler, drawn as pictures (as Mitsuba 3's chi2
// module draws its own). For one material and one incident direction, the directions
// bsdf_sample draws are counted in cells of (cos theta, phi) over the whole sphere; beside
// them, the counts bsdf_pdf promises for the same cells; and the counts of a wrong twin, a
// sampler with one deliberate mistake. A sampler that agrees with its density gives the first
// two panels alike, noise aside; the twin's differs where its mistake lies.
//
//   ch12_chi2_maps [--material NAME] [--roughness R] [--theta DEGREES] [--samples N]
//                  [--cells-cos N] [--cells-phi N] [--cell-pixels N] [--output FILE.png]
#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "bsdf.h"
#include "energy_compensation.h"
#include "material_scenes.h"
#include "path_random.h"
#include "rt/cli.h"
#include "rt/error.h"
#include "rt/image.h"
#include "rt/report.h"

namespace {

using namespace rt;
using namespace rt::ch12;

constexpr double k_two_pi = 2.0 * std::numbers::pi;

struct Options {
  std::string material = "rough-glass";
  double roughness = -1.0; // the material's own
  double theta_degrees = 60.0;
  int samples = 1000000;
  int cells_cos = 48, cells_phi = 96, cell_pixels = 3;
  std::string output = "ch12_chi2_maps.png";
};

// The material at a hit with no textures: what surface_at (material_trace.h) makes of it.
Bsdf bsdf_of(const Material& m) {
  return {m.model,        m.base_color, m.metallic, alpha_of(m.roughness), m.ior,
          m.transmission, m.eta,        m.k,        m.conductor_f_avg};
}

// Counts per cell: rows are cos(theta) from 1 (the normal, top row) down to -1, columns phi
// from 0 to 2 pi. Equal steps in cos(theta) and phi make cells of equal solid angle.
struct Grid {
  int rows, columns;
  std::vector<double> count;
  Grid(int r, int c) : rows(r), columns(c), count(std::size_t(r) * c, 0.0) {}
  double cell_solid_angle() const { return (2.0 / rows) * (k_two_pi / columns); }
  int cell_of(Vec3d d) const {
    const double cosine = std::clamp(d.z / length(d), -1.0, 1.0);
    double phi = std::atan2(d.y, d.x);
    if (phi < 0.0) phi += k_two_pi;
    const int row = std::clamp(int((1.0 - cosine) / 2.0 * rows), 0, rows - 1);
    const int column = std::clamp(int(phi / k_two_pi * columns), 0, columns - 1);
    return row * columns + column;
  }
  // The direction at (a, b) in [0, 1]^2 of cell (row, column).
  Vec3d direction(int row, int column, double a, double b) const {
    const double cosine = 1.0 - 2.0 * (row + a) / rows;
    const double phi = k_two_pi * (column + b) / columns;
    const double sine = std::sqrt(std::max(0.0, 1.0 - cosine * cosine));
    return {sine * std::cos(phi), sine * std::sin(phi), cosine};
  }
};

// [listing:chi2_histograms]
// What `samples` draws of the sampler put in each cell; a draw that gives no direction (a
// reflection below the horizon, light the surface absorbs) counts nowhere.
Grid observed_counts(const Options& o, const std::function<bool(int, Vec3f&)>& sample) {
  Grid grid(o.cells_cos, o.cells_phi);
  for (int i = 0; i < o.samples; ++i) {
    Vec3f wi;
    if (sample(i, wi)) grid.count[grid.cell_of(wi.as<double>())] += 1.0;
  }
  return grid;
}

// What the density promises each cell: samples times the integral of the pdf over it, by the
// midpoint rule (cells are equal in solid angle, so no Jacobian). A rough dielectric's density
// jumps where a microfacet would be seen from behind, and the midpoint rule converges slowly
// across a jump: about 800 points from pole to pole keep its error below the counts' noise.
Grid expected_counts(const Options& o, const std::function<double(Vec3d)>& pdf) {
  const int k_points = std::max(4, 800 / o.cells_cos);
  Grid grid(o.cells_cos, o.cells_phi);
  const double weight = o.samples * grid.cell_solid_angle() / (k_points * k_points);
  for (int row = 0; row < grid.rows; ++row)
    for (int column = 0; column < grid.columns; ++column) {
      double sum = 0.0;
      for (int a = 0; a < k_points; ++a)
        for (int b = 0; b < k_points; ++b)
          sum += pdf(grid.direction(row, column, (a + 0.5) / k_points, (b + 0.5) / k_points));
      grid.count[row * grid.columns + column] = weight * sum;
    }
  return grid;
}
// [/listing:chi2_histograms]

// Pearson's statistic over the cells, those expecting fewer than 5 samples pooled into one
// (the statistic follows the chi-square law only where every cell expects a few), and how
// many standard deviations it lies above its mean: for D degrees of freedom the statistic has
// mean D and variance 2 D, so a right sampler gives z of order 1.
struct Fit {
  double statistic = 0.0, z = 0.0;
  int degrees_of_freedom = 0;
};
Fit pearson(const Grid& observed, const Grid& expected) {
  Fit fit;
  double pooled_observed = 0.0, pooled_expected = 0.0;
  int cells = 0;
  for (std::size_t i = 0; i < expected.count.size(); ++i) {
    if (expected.count[i] < 5.0) {
      pooled_observed += observed.count[i];
      pooled_expected += expected.count[i];
      continue;
    }
    const double d = observed.count[i] - expected.count[i];
    fit.statistic += d * d / expected.count[i];
    ++cells;
  }
  if (pooled_expected > 0.0) {
    const double d = pooled_observed - pooled_expected;
    fit.statistic += d * d / pooled_expected;
    ++cells;
  }
  fit.degrees_of_freedom = std::max(1, cells - 1);
  fit.z = (fit.statistic - fit.degrees_of_freedom) / std::sqrt(2.0 * fit.degrees_of_freedom);
  return fit;
}

// A perceptual colour map (viridis, five stops), t in [0, 1].
Rgba8 colour_of(double t) {
  static constexpr double k_stops[5][3] = {
      {68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  t = std::clamp(t, 0.0, 1.0) * 4.0;
  const int i = std::min(int(t), 3);
  const double f = t - i;
  const auto channel = [&](int c) {
    return std::uint8_t(std::lround(k_stops[i][c] + (k_stops[i + 1][c] - k_stops[i][c]) * f));
  };
  return {channel(0), channel(1), channel(2), 255};
}

// The three grids side by side, 4 grey pixels apart, on one scale: logarithmic over three
// decades below the largest count expected, so that the tail of a lobe shows beside its peak.
Image draw(const std::vector<const Grid*>& panels, int cell_pixels, double largest) {
  constexpr int k_gap = 4;
  const Grid& first = *panels.front();
  const int panel_width = first.columns * cell_pixels, height = first.rows * cell_pixels;
  const int count = int(panels.size());
  const double floor = largest * 1e-3;
  Image image(count * panel_width + (count - 1) * k_gap, height);
  for (Rgba8& p : image.pixels) p = {96, 96, 96, 255};
  for (int k = 0; k < count; ++k)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < panel_width; ++x) {
        const double n = panels[k]->count[(y / cell_pixels) * first.columns + x / cell_pixels];
        image.at(k * (panel_width + k_gap) + x, y) =
            colour_of(std::log1p(n / floor) / std::log1p(1e3));
      }
  return image;
}

int run(const Options& o) {
  if (!o.output.ends_with(".png"))
    throw UsageError("--output " + o.output + ": the maps are a picture, a .png file");
  check_image_path(o.output);
  const Material material = named_material(o.material, float(o.roughness));
  const Bsdf bsdf = bsdf_of(material);
  if (bsdf_has_smooth_lobe(bsdf))
    throw UsageError(o.material + " at roughness " + format_fixed(material.roughness, 3) +
                     " has a smooth lobe, a single direction with no density to draw: give "
                     "--roughness above 0.001");
  const CompensationTable table;
  const CompensationView view = table.view(true);
  const double theta = o.theta_degrees * std::numbers::pi / 180.0;
  const Vec3f wo{float(std::sin(theta)), 0.0f, float(std::cos(theta))};

  // [listing:chi2_twin]
  // The twin: a microfacet material drawn as if its alpha were 1.5 times larger (the lobe too
  // wide; 1.5 times smaller where that would pass 1, the largest alpha), a Lambertian one
  // drawn uniformly over the hemisphere instead of by the cosine. Its directions are counted
  // against the right density. Rough glass is drawn with its energy compensation on.
  Bsdf twin = bsdf;
  if (twin.model != MaterialModel::lambertian)
    twin.alpha = 1.5f * bsdf.alpha <= 1.0f ? 1.5f * bsdf.alpha : bsdf.alpha / 1.5f;
  const bool uniform_twin = bsdf.model == MaterialModel::lambertian;
  const auto sampler = [&](const Bsdf& b, unsigned seed, bool uniform) {
    return [&b, &view, wo, seed, uniform](int i, Vec3f& wi) {
      const auto u = [&](unsigned d) { return ch11::sample_number(unsigned(i), seed, 1, d); };
      if (uniform) {
        const float z = u(1), phi = float(k_two_pi) * u(2);
        const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        wi = {r * std::cos(phi), r * std::sin(phi), z};
        return true;
      }
      BsdfSample s;
      if (!bsdf_sample(b, wo, u(0), u(1), u(2), view, s)) return false;
      wi = s.wi;
      return true;
    };
  };
  const Grid observed = observed_counts(o, sampler(bsdf, 1, false));
  const Grid wrong = observed_counts(o, sampler(twin, 2, uniform_twin));
  const Grid expected = expected_counts(
      o, [&](Vec3d d) { return double(bsdf_pdf(bsdf, wo, d.as<float>(), view)); });
  // [/listing:chi2_twin]

  const double largest = *std::max_element(expected.count.begin(), expected.count.end());
  if (!(largest > 0.0))
    throw InputError(o.material + ": bsdf_pdf is 0 in every cell: nothing to draw");
  write_png(o.output, draw({&observed, &expected, &wrong}, o.cell_pixels, largest));
  const auto say = [](const char* who, const Fit& f) {
    std::cout << who << ": chi-square " << format_fixed(f.statistic, 1) << " on "
              << f.degrees_of_freedom << " degrees of freedom, z = " << format_fixed(f.z, 1)
              << "\n";
  };
  std::cout << o.material
            << (bsdf.model == MaterialModel::lambertian
                    ? std::string()
                    : ", roughness " + format_fixed(material.roughness, 3))
            << ", theta_o " << format_fixed(o.theta_degrees, 1) << " degrees, " << o.samples
            << " samples in " << o.cells_cos << " x " << o.cells_phi
            << " cells of (cos theta, phi)\n";
  say("bsdf_sample", pearson(observed, expected));
  say(uniform_twin              ? "wrong twin (uniform hemisphere)"
      : twin.alpha > bsdf.alpha ? "wrong twin (alpha x 1.5)"
                                : "wrong twin (alpha / 1.5)",
      pearson(wrong, expected));
  std::cout << "wrote " << o.output << " (observed | expected | wrong twin observed)\n";
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 12: a BSDF's samples against its density, drawn (observed | expected "
               "| a wrong sampler's observed)",
               "ch12_chi2_maps"};
  Options o;
  app.add_option("--material", o.material, "The material (" + material_names() + ")")
      ->capture_default_str();
  app.add_option("--roughness", o.roughness, "Its roughness (default: the material's own)")
      ->check(finite_range(0.0, 1.0));
  app.add_option("--theta", o.theta_degrees,
                 "Angle of the incident direction from the normal, in degrees")
      ->check(finite_range(0.0, 89.9))
      ->capture_default_str();
  app.add_option("--samples", o.samples, "Directions drawn by each sampler")
      ->check(CLI::Range(1000, 100000000))
      ->capture_default_str();
  app.add_option("--cells-cos", o.cells_cos, "Cells in cos(theta), from 1 to -1")
      ->check(CLI::Range(2, 1024))
      ->capture_default_str();
  app.add_option("--cells-phi", o.cells_phi, "Cells in phi, from 0 to 2 pi")
      ->check(CLI::Range(2, 1024))
      ->capture_default_str();
  app.add_option("--cell-pixels", o.cell_pixels, "Pixels on a side of a cell in the picture")
      ->check(CLI::Range(1, 16))
      ->capture_default_str();
  app.add_option("--output", o.output, "The picture, a .png file")->capture_default_str();
  return run_main(app, argc, argv, [&] { return run(o); });
}
