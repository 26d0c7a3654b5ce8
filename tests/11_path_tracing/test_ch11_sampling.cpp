// Chapter 11 tests of every sampler the path tracer draws with, against the density its
// estimators divide by: Pearson's chi-square test (tests/support/chi_square.h) on histograms
// of many samples, as pbrt-v4 and Mitsuba 3 test theirs. The cosine-weighted bounce is
// histogrammed over the sphere in (cos theta, phi) cells, points on triangles and emitters in
// equal sub-triangles, the camera's point in its pixel on a grid; the expected counts come
// from integrating the density over each cell. Each sampler also gets a deliberately wrong
// twin that the same test must reject. The numbers come from the chapter's stateless hash, so
// every run draws the same samples.
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "rt_catch.h"

#include "chi_square.h"
#include "path_cases.h"

using namespace rt;
using namespace rt::ch11;
using namespace rt::ch11::testing;
using rt::testing::chi_square_test;
using rt::testing::ChiSquare;

namespace {

// A correct sampler fails one of the k_fit_tests goodness-of-fit tests below with
// probability k_alpha in all; each test asks for the corrected level. A wrong sampler must
// fall below the same level.
constexpr double k_alpha = 0.01;
constexpr int k_fit_tests = 11; // 6 normals, 3 triangles, the emitters, the camera
const double k_level = rt::testing::corrected_significance(k_alpha, k_fit_tests);

constexpr double k_two_pi = 2.0 * std::numbers::pi;
constexpr int k_samples = 200000;

Vec3d to_double(Vec3f v) { return {v.x, v.y, v.z}; }

// The observed counts of `cells` cells: cell_of(i) for sample i, or -1 for a sample outside
// every cell (counted as stray: a cell that expects nothing).
std::vector<double> histogram(int cells, int samples, const std::function<int(int)>& cell_of) {
  std::vector<double> counts(static_cast<std::size_t>(cells) + 1, 0.0);
  for (int i = 0; i < samples; ++i) {
    const int cell = cell_of(i);
    counts[cell < 0 || cell >= cells ? static_cast<std::size_t>(cells)
                                     : static_cast<std::size_t>(cell)] += 1.0;
  }
  return counts;
}

ChiSquare fit(const std::vector<double>& observed, std::vector<double> expected) {
  expected.resize(observed.size(), 0.0); // the stray cell expects nothing
  return chi_square_test(observed, expected);
}

// ---------------------------------------------------------------------------------------------
// Directions: cells over the whole sphere, in cos(theta) and phi about the normal, so that a
// direction below the surface lands in a cell that expects nothing.

constexpr int k_cosine_cells = 20; // from -1 to 1: 10 below the surface, 10 above
constexpr int k_phi_cells = 24;

// A frame about n of the test's own, in double (the azimuth's origin is arbitrary), so the
// histogram does not lean on the Duff frame it tests.
struct FrameD {
  Vec3d tangent, bitangent, normal;
};
FrameD frame_about(Vec3d n) {
  n = normalize(n);
  const Vec3d helper = std::abs(n.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  const Vec3d tangent = normalize(cross(helper, n));
  return {tangent, cross(n, tangent), n};
}

int sphere_cell(const FrameD& f, Vec3d d) {
  d = normalize(d);
  const double cosine = std::clamp(dot(d, f.normal), -1.0, 1.0);
  double phi = std::atan2(dot(d, f.bitangent), dot(d, f.tangent));
  if (phi < 0.0) phi += k_two_pi;
  const int i = std::min(int((cosine + 1.0) * 0.5 * k_cosine_cells), k_cosine_cells - 1);
  const int j = std::min(int(phi / k_two_pi * k_phi_cells), k_phi_cells - 1);
  return i * k_phi_cells + j;
}

// Samples times the density (per solid angle, a function of cos theta and phi) integrated
// over each cell by Simpson's rule; the solid angle is d(cos theta) d(phi).
std::vector<double> sphere_expectation(const std::function<double(double, double)>& density,
                                       double samples) {
  constexpr int k_steps = 4; // Simpson intervals per cell and axis (even)
  std::vector<double> expected(k_cosine_cells * k_phi_cells);
  const double dc = 2.0 / k_cosine_cells, dphi = k_two_pi / k_phi_cells;
  const auto weight = [](int k) { return k == 0 || k == k_steps ? 1.0 : (k % 2 ? 4.0 : 2.0); };
  for (int i = 0; i < k_cosine_cells; ++i)
    for (int j = 0; j < k_phi_cells; ++j) {
      double sum = 0.0;
      for (int a = 0; a <= k_steps; ++a)
        for (int b = 0; b <= k_steps; ++b)
          sum +=
              weight(a) * weight(b) *
              density(-1.0 + dc * (i + double(a) / k_steps), dphi * (j + double(b) / k_steps));
      expected[i * k_phi_cells + j] =
          samples * sum * (dc / k_steps / 3.0) * (dphi / k_steps / 3.0);
    }
  return expected;
}

double cosine_density_at(double cosine, double) { return cosine_density(float(cosine)); }

std::vector<Vec3f> test_normals() {
  return {Vec3f{0, 0, 1},                        // the frame's own axis
          Vec3f{0, 0, -1},                       // the other pole, where Duff's sign flips
          normalize(Vec3f{1e-4f, 0, -1}),        // next to it
          Vec3f{0, 1, 0},                        // a wall's normal: n.z = 0
          normalize(Vec3f{1, -2, 0.1f}),         // nowhere special
          normalize(Vec3f{-0.3f, 0.5f, -0.8f})}; // below the horizon of z
}

// The chi-square test of a direction sampler about n, with the cosine density as the law.
ChiSquare fit_directions(Vec3f n, unsigned seed,
                         const std::function<Vec3f(Vec3f, float, float)>& sampler) {
  const FrameD frame = frame_about(to_double(n));
  const std::vector<double> observed =
      histogram(k_cosine_cells * k_phi_cells, k_samples, [&](int i) {
        const float u = sample_number(unsigned(i), seed, 1, k_bsdf_u);
        const float v = sample_number(unsigned(i), seed, 1, k_bsdf_v);
        return sphere_cell(frame, to_double(sampler(n, u, v)));
      });
  return fit(observed, sphere_expectation(cosine_density_at, k_samples));
}

// ---------------------------------------------------------------------------------------------
// Points on a triangle: k_edge_cells^2 sub-triangles of equal area, cut by lines parallel to
// the edges, found from the point's barycentric coordinates.

constexpr int k_edge_cells = 12;
constexpr int k_triangle_cells = 2 * k_edge_cells * k_edge_cells; // a lower and an upper half
                                                                  // per grid square

// The sub-triangle of p in triangle (v0, v1, v2), or -1 for a point off the triangle by more
// than rounding explains.
int triangle_cell(Vec3d v0, Vec3d v1, Vec3d v2, Vec3d p) {
  const Vec3d e1 = v1 - v0, e2 = v2 - v0, w = p - v0;
  const double a = dot(e1, e1), b = dot(e1, e2), c = dot(e2, e2);
  const double det = a * c - b * b;
  double b1 = (c * dot(w, e1) - b * dot(w, e2)) / det;
  double b2 = (a * dot(w, e2) - b * dot(w, e1)) / det;
  constexpr double k_rounding = 1e-5;
  if (b1 < -k_rounding || b2 < -k_rounding || b1 + b2 > 1.0 + k_rounding) return -1;
  b1 = std::clamp(b1, 0.0, 1.0);
  b2 = std::clamp(b2, 0.0, 1.0);
  const double x = b1 * k_edge_cells, y = b2 * k_edge_cells;
  int i = std::min(int(x), k_edge_cells - 1), j = std::min(int(y), k_edge_cells - 1);
  if (i + j > k_edge_cells - 1) j = k_edge_cells - 1 - i; // past the far edge by rounding
  const bool upper = i + j < k_edge_cells - 1 && (x - i) + (y - j) > 1.0;
  return (i * k_edge_cells + j) * 2 + (upper ? 1 : 0);
}

// `samples` points of uniform density spread over the sub-triangles: a grid square below the
// far edge holds two, one on it only its lower half.
std::vector<double> triangle_expectation(double samples) {
  std::vector<double> expected(k_triangle_cells, 0.0);
  const double per_cell = samples / (k_edge_cells * k_edge_cells);
  for (int i = 0; i < k_edge_cells; ++i)
    for (int j = 0; i + j < k_edge_cells; ++j) {
      expected[(i * k_edge_cells + j) * 2] = per_cell;
      if (i + j < k_edge_cells - 1) expected[(i * k_edge_cells + j) * 2 + 1] = per_cell;
    }
  return expected;
}

struct TriangleCase {
  Vec3f v0, v1, v2;
};
std::vector<TriangleCase> test_triangles() {
  return {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},                // right-angled, at the origin
          {{0.2f, -1, 3}, {4, 0.5f, 2.5f}, {-1, 2, 0.7f}},  // oblique, in no axis plane
          {{10, 10, 10}, {10.5f, 10, 10}, {14, 10.2f, 9}}}; // obtuse and long
}

using PointSampler = std::function<Vec3f(const TriangleCase&, float, float)>;

ChiSquare fit_triangle(const TriangleCase& t, unsigned seed, const PointSampler& sampler) {
  const std::vector<double> observed = histogram(k_triangle_cells, k_samples, [&](int i) {
    const float u = sample_number(unsigned(i), seed, 1, k_light_u);
    const float v = sample_number(unsigned(i), seed, 1, k_light_v);
    return triangle_cell(to_double(t.v0), to_double(t.v1), to_double(t.v2),
                         to_double(sampler(t, u, v)));
  });
  return fit(observed, triangle_expectation(k_samples));
}

// ---------------------------------------------------------------------------------------------
// Emitters: four triangles whose shares of the power differ from their shares of the area,
// and one that does not emit.

PathScene emitter_scene() {
  PathScene scene;
  scene.mesh.vertices = {{0, 0, 0},   {1, 0, 0},   {0, 1, 0},      // area 0.5
                         {2, 0, 0},   {5, 0, 0},   {2, 2, 0},      // area 3
                         {0, 3, 1},   {1, 3, 1},   {0, 3, 3},      // area 1
                         {-2, -2, 0}, {-1, -2, 0}, {-2, -1.5f, 0}, // area 0.25
                         {0, 0, 5},   {9, 0, 5},   {0, 9, 5}};     // does not emit
  scene.mesh.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {9, 10, 11}, {12, 13, 14}};
  const Vec3f grey{0.5f, 0.5f, 0.5f};
  scene.materials = {{grey, {1, 1, 1}},
                     {grey, {0.2f, 0.2f, 0.2f}},
                     {grey, {4, 1, 0.5f}},
                     {grey, {0, 6, 0}},
                     {grey, {0, 0, 0}}};
  scene.material = {0, 1, 2, 3, 4};
  scene.lights = build_light_table(scene);
  return scene;
}

// The scene as the kernels see it, with the light table `table` (the scene's, or a wrong one).
PathSceneView view_of(const PathScene& scene, const LightTable& table) {
  PathSceneView view{};
  view.mesh = ch04::host_view(scene.mesh);
  view.material = scene.material.data();
  view.materials = scene.materials.data();
  view.light_triangles = table.triangles.data();
  view.light_cdf = table.cdf.data();
  view.light_count = static_cast<int>(table.triangles.size());
  view.light_power = static_cast<float>(scene.lights.power);
  return view;
}

double triangle_area(const ch04::TriangleF& t) {
  return 0.5 * length(cross(to_double(t.v1 - t.v0), to_double(t.v2 - t.v0)));
}

// The emitters' sub-triangles, light by light. The expected counts integrate the density the
// estimators divide by, light_area_density, over each sub-triangle's area.
ChiSquare fit_emitters(const PathScene& scene, const LightTable& table,
                       double* expected_total) {
  const PathSceneView truth = view_of(scene, scene.lights), drawn = view_of(scene, table);
  const int lights = static_cast<int>(table.triangles.size());
  const std::vector<double> observed =
      histogram(lights * k_triangle_cells, k_samples, [&](int i) {
        const LightPoint p =
            sample_light_point(drawn, sample_number(unsigned(i), 7, 1, k_light_pick),
                               sample_number(unsigned(i), 7, 1, k_light_u),
                               sample_number(unsigned(i), 7, 1, k_light_v));
        const auto slot = std::find(table.triangles.begin(), table.triangles.end(), p.triangle);
        if (slot == table.triangles.end()) return -1; // not an emitter at all
        const ch04::TriangleF t = scene.mesh.triangle(p.triangle);
        const int cell = triangle_cell(to_double(t.v0), to_double(t.v1), to_double(t.v2),
                                       to_double(p.point));
        return cell < 0 ? -1 : int(slot - table.triangles.begin()) * k_triangle_cells + cell;
      });
  std::vector<double> expected;
  *expected_total = 0.0;
  for (const int triangle : table.triangles) {
    const double area = triangle_area(scene.mesh.triangle(triangle));
    const Vec3f emission = scene.materials[scene.material[triangle]].emission;
    const double share = double(light_area_density(truth, emission)) * area;
    for (const double uniform : triangle_expectation(k_samples)) {
      expected.push_back(uniform * share);
      *expected_total += uniform * share;
    }
  }
  return fit(observed, expected);
}

// ---------------------------------------------------------------------------------------------
// The camera's point in its pixel: where the ray crosses the image plane, in pixels, minus the
// pixel's corner; a k_pixel_cells x k_pixel_cells grid over the pixel.

constexpr int k_pixel_cells = 12;

int pixel_cell(const ch03::Camera<float>& camera, const RayF& ray, int x, int y) {
  const auto& c = camera.pinhole;
  const Vec3d d = to_double(ray.direction);
  const double forward = dot(d, to_double(c.basis.forward));
  const double sx = dot(d, to_double(c.basis.right)) / forward;
  const double sy = dot(d, to_double(c.basis.up)) / forward;
  double ox = (sx / (double(c.tan_half_vfov) * c.aspect) + 1.0) * 0.5 * c.width - x;
  double oy = (1.0 - sy / double(c.tan_half_vfov)) * 0.5 * c.height - y;
  constexpr double k_rounding = 1e-4;
  if (ox < -k_rounding || oy < -k_rounding || ox > 1.0 + k_rounding || oy > 1.0 + k_rounding)
    return -1;
  const int i = std::clamp(int(ox * k_pixel_cells), 0, k_pixel_cells - 1);
  const int j = std::clamp(int(oy * k_pixel_cells), 0, k_pixel_cells - 1);
  return j * k_pixel_cells + i;
}

ChiSquare fit_camera(const ch03::Camera<float>& camera, int x, int y,
                     const std::function<RayF(int)>& ray_of_sample) {
  constexpr int k_cells = k_pixel_cells * k_pixel_cells;
  const std::vector<double> observed = histogram(
      k_cells, k_samples, [&](int i) { return pixel_cell(camera, ray_of_sample(i), x, y); });
  return fit(observed, std::vector<double>(k_cells, double(k_samples) / k_cells));
}

void report(const ChiSquare& r) {
  UNSCOPED_INFO("chi-square " << r.statistic << " on " << r.degrees_of_freedom
                              << " degrees of freedom, p = " << r.p_value << ", " << r.stray
                              << " stray samples; the level is " << k_level);
}

} // namespace

TEST_CASE("chi-square: the law's upper tail, and cells pooled where few are expected",
          "[ch11]") {
  using rt::testing::chi_square_upper_tail;
  // Tabulated quantiles of the chi-square law.
  CHECK(chi_square_upper_tail(3.841459, 1) == Approx(0.05).epsilon(1e-4));
  CHECK(chi_square_upper_tail(6.634897, 1) == Approx(0.01).epsilon(1e-4));
  CHECK(chi_square_upper_tail(18.307038, 10) == Approx(0.05).epsilon(1e-4));
  CHECK(chi_square_upper_tail(124.342113, 100) == Approx(0.05).epsilon(1e-4));
  // With 2 degrees of freedom the tail is exp(-x / 2), deep into the tail too.
  for (const double x : {0.5, 3.0, 40.0, 300.0})
    CHECK(chi_square_upper_tail(x, 2) == Approx(std::exp(-0.5 * x)).epsilon(1e-10));
  CHECK(chi_square_upper_tail(0.0, 7) == 1.0);

  // Five cells of 1 pool into one of 5; the others stand alone.
  const std::vector<double> expected{1, 1, 10, 1, 1, 10, 1};
  const ChiSquare pooled = chi_square_test(std::vector<double>{0, 2, 12, 1, 1, 9, 1}, expected);
  CHECK(pooled.degrees_of_freedom == 2);
  CHECK(pooled.statistic == Approx(0.4 + 0.1));
  CHECK(pooled.p_value == Approx(std::exp(-0.25)));
  // A sample where none is expected fails the test whatever the rest.
  const ChiSquare stray =
      chi_square_test(std::vector<double>{1, 10, 10}, std::vector<double>{0, 10, 10});
  CHECK(stray.stray == 1.0);
  CHECK(stray.p_value == 0.0);
  CHECK(rt::testing::corrected_significance(0.01, 1) == Approx(0.01));
  CHECK(rt::testing::corrected_significance(0.01, 10) == Approx(0.001005).epsilon(1e-3));
}

TEST_CASE("the cosine-weighted bounce has density cos(theta) / pi about every normal, the "
          "poles included",
          "[ch11]") {
  const std::vector<double> expected = sphere_expectation(cosine_density_at, k_samples);
  double total = 0.0;
  for (const double e : expected) total += e;
  CHECK(total == Approx(k_samples).epsilon(1e-6)); // the density integrates to 1
  unsigned seed = 100;
  for (const Vec3f n : test_normals()) {
    CAPTURE(n.x, n.y, n.z);
    double worst_length = 0.0, worst_pdf = 0.0;
    const ChiSquare r = fit_directions(n, seed++, [&](Vec3f normal, float u, float v) {
      const DirectionSample s = sample_cosine(normal, u, v);
      worst_length = std::max(worst_length, std::abs(double(length(s.direction)) - 1.0));
      const double pdf = cosine_density_at(dot(to_double(s.direction), to_double(normal)), 0);
      worst_pdf = std::max(worst_pdf, std::abs(s.pdf - pdf));
      return s.direction;
    });
    report(r);
    CHECK(r.p_value > k_level);
    CHECK(worst_length < 1e-6);
    // The density it reports is the density of the direction it returns, up to the rounding
    // of a float frame (a few 1e-8 in cos theta).
    CHECK(worst_pdf < 1e-6);
  }
}

TEST_CASE("the chi-square test rejects a cosine sampler with a wrong azimuth or radius",
          "[ch11]") {
  const auto half_turn = [](Vec3f n, float u, float v) { // phi = pi v instead of 2 pi v
    const float s = std::sqrt(u);
    return ch07::turn_to_normal(
        n, {s * std::cos(k_pi * v), s * std::sin(k_pi * v), std::sqrt(1.0f - u)});
  };
  const auto linear_radius = [](Vec3f n, float u, float v) { // the disc's radius u, not sqrt u
    const ch07::SinCos phi = ch07::sin_cos_turns(v);
    return ch07::turn_to_normal(n, {u * phi.cos, u * phi.sin, std::sqrt(1.0f - u * u)});
  };
  unsigned seed = 100;
  for (const Vec3f n : test_normals()) {
    CAPTURE(n.x, n.y, n.z);
    const ChiSquare azimuth = fit_directions(n, seed, half_turn);
    report(azimuth);
    CHECK(azimuth.p_value < k_level);
    const ChiSquare radius = fit_directions(n, seed++, linear_radius);
    report(radius);
    CHECK(radius.p_value < k_level);
  }
}

TEST_CASE(
    "points on a triangle are uniform over its area, and without the square root they are "
    "not",
    "[ch11]") {
  unsigned seed = 200;
  for (const TriangleCase& t : test_triangles()) {
    CAPTURE(t.v0.x, t.v1.x, t.v2.x);
    const ChiSquare right = fit_triangle(t, seed, [](const TriangleCase& c, float u, float v) {
      return point_on_triangle(c.v0, c.v1, c.v2, u, v);
    });
    report(right);
    CHECK(right.p_value > k_level);
    const ChiSquare no_root =
        fit_triangle(t, seed++, [](const TriangleCase& c, float u, float v) {
          const float b0 = 1.0f - u, b1 = v * u; // point_on_triangle with s = u
          return c.v0 * b0 + c.v1 * b1 + c.v2 * (1.0f - b0 - b1);
        });
    report(no_root);
    CHECK(no_root.p_value < k_level);
  }
}

TEST_CASE("next-event estimation's points: density luminance / power per area on every "
          "emitter, and a pick by area alone is rejected",
          "[ch11]") {
  const PathScene scene = emitter_scene();
  REQUIRE(scene.lights.triangles == std::vector<int>{0, 1, 2, 3});
  double total = 0.0;
  const ChiSquare right = fit_emitters(scene, scene.lights, &total);
  report(right);
  CHECK(right.p_value > k_level);
  CHECK(total == Approx(k_samples).epsilon(1e-6)); // the density integrates to 1

  LightTable by_area = scene.lights; // the same emitters, picked by their area alone
  double area = 0.0;
  for (std::size_t k = 0; k < by_area.triangles.size(); ++k) {
    area += triangle_area(scene.mesh.triangle(by_area.triangles[k]));
    by_area.cdf[k] = static_cast<float>(area);
  }
  for (float& c : by_area.cdf) c = static_cast<float>(c / area);
  by_area.cdf.back() = 1.0f;
  const ChiSquare wrong = fit_emitters(scene, by_area, &total);
  report(wrong);
  CHECK(wrong.p_value < k_level);
}

TEST_CASE("the camera's ray crosses its pixel at a uniform point, and a squared offset is "
          "rejected",
          "[ch11]") {
  const Extent extent{5, 4};
  const ch03::Camera<float> camera = ch03::make_camera<float>(cornell_camera(), extent);
  const int x = 3, y = 1;
  const ChiSquare right = fit_camera(
      camera, x, y, [&](int i) { return start_path(camera, x, y, unsigned(i)).ray; });
  report(right);
  CHECK(right.p_value > k_level);
  const ChiSquare squared = fit_camera(camera, x, y, [&](int i) {
    const unsigned pixel = unsigned(y * extent.width + x);
    const float u = sample_number(pixel, unsigned(i), 0, 0),
                v = sample_number(pixel, unsigned(i), 0, 1);
    return camera_ray_jittered(camera, x, y, u * u - 0.5f, v - 0.5f);
  });
  report(squared);
  CHECK(squared.p_value < k_level);
}
