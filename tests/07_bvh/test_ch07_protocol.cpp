// Chapter 07 tests of the benchmark protocol: the pixel hash against its published vectors, the
// camera against the formula evaluated in double, the views, the Duff frame and the cosine
// distribution, the faced normal, secondary rays (where they start, how far they reach, which
// pixels get one), ray and hit files with every malformed case, and on the GPU the same rays
// bit for bit.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "bvh_cases.h"

#include "gpu_guard.h"
#include "protocol.h"
#include "ray_io.h"
#include "rt/device_buffer.h"
#include "rt/error.h"
#include "triangles.h"

using namespace rt;
using namespace rt::ch07;
using rt::testing::contains;
using rt::testing::count_hits;
using rt::testing::same_bits;

namespace {

constexpr float k_inf = std::numeric_limits<float>::infinity();
constexpr float k_nan = std::numeric_limits<float>::quiet_NaN();

Vec3d to_double(Vec3f v) { return v.as<double>(); }

Vec3d cross_d(Vec3d a, Vec3d b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

Vec3d normalize_d(Vec3d v) { return v / std::sqrt(dot(v, v)); }

double distance_d(Vec3d a, Vec3d b) { return std::sqrt(length_squared(a - b)); }

// Unit normals spread over the sphere (a Fibonacci spiral), plus the poles and the places where
// frame constructions break: n.z = -1 and just beside it, n.z = -0, the equator.
std::vector<Vec3f> test_normals() {
  std::vector<Vec3f> normals = {{0, 0, 1},       {0, 0, -1},          {1, 0, 0},
                                {0, 1, 0},       {-1, 0, 0},          {0, -1, 0},
                                {1, 0, -0.0f},   {0.6f, 0.8f, -0.0f}, {1e-7f, 0, -1},
                                {0, -3e-4f, -1}, {2e-4f, 1e-4f, -1},  {1e-20f, 1e-20f, -1}};
  constexpr int k_spiral = 2000;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < k_spiral; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / k_spiral;
    const double radius = std::sqrt(1.0 - z * z);
    normals.push_back(
        Vec3d{radius * std::cos(golden * k), radius * std::sin(golden * k), z}.as<float>());
  }
  for (Vec3f& n : normals) n = normalize(n);
  return normals;
}

Aabb bounds_of(const ch04::Mesh& mesh) {
  Aabb box;
  for (const Vec3f& v : mesh.vertices) box.grow(v);
  return box;
}

// A temporary file, removed when the test ends.
struct TempFile {
  std::string path;
  explicit TempFile(const std::string& name)
      : path((std::filesystem::temp_directory_path() / ("rt_ch07_" + name)).string()) {
    std::filesystem::remove(path);
  }
  ~TempFile() {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
  }
  void write_bytes(const void* data, std::size_t bytes) const {
    std::ofstream out(path, std::ios::binary);
    out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
  }
};

// One frame of the protocol on the CPU: the camera, its rays and their closest hits.
struct Frame {
  PinholeCamera camera;
  std::vector<RayF> rays;
  std::vector<MeshHit> hits;
};

Frame trace_frame(const ch04::Mesh& mesh, Vec3f eye, Vec3f target, int width, int height) {
  Frame frame{make_protocol_camera(eye, target, 60.0f, width, height), {}, {}};
  frame.rays = camera_rays_cpu(frame.camera);
  frame.hits = ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, frame.rays);
  return frame;
}

// The message of the E that f throws. Throwing nothing fails the test; throwing another type
// escapes, which fails it too.
template <class E, class F> std::string thrown_message(F&& f) {
  try {
    f();
  } catch (const E& error) {
    return error.what();
  }
  FAIL("expected an exception, none was thrown");
  return {};
}

} // namespace

// ---------------------------------------------------------------------------------------------
// The pixel hash.

TEST_CASE("pcg2d gives the protocol's test vectors exactly", "[ch07]") {
  CHECK(same_bits(pcg2d_uniforms(0, 0), Vec2f{0.0972319245f, 0.0209648609f}));
  CHECK(same_bits(pcg2d_uniforms(1, 0), Vec2f{0.616393149f, 0.521409571f}));
  CHECK(same_bits(pcg2d_uniforms(960, 540), Vec2f{0.811587811f, 0.0957951546f}));
}

TEST_CASE("pcg2d uniforms are multiples of 2^-24 from 0 to below 1, evenly spread", "[ch07]") {
  constexpr int k_side = 256;
  std::vector<int> histogram(16, 0);
  for (int j = 0; j < k_side; ++j)
    for (int i = 0; i < k_side; ++i) {
      const Vec2f u = pcg2d_uniforms(i, j);
      REQUIRE(u.x >= 0.0f);
      REQUIRE(u.x < 1.0f);
      REQUIRE(u.y >= 0.0f);
      REQUIRE(u.y < 1.0f);
      REQUIRE(std::ldexp(u.x, 24) == std::floor(std::ldexp(u.x, 24)));
      ++histogram[static_cast<int>(u.x * 4) * 4 + static_cast<int>(u.y * 4)];
    }
  // 65536 pairs in 16 cells: 4096 expected each, standard deviation ~62.
  for (int cell : histogram) CHECK(std::abs(cell - 4096) < 400);
}

// ---------------------------------------------------------------------------------------------
// sin and cos of an angle in turns.

TEST_CASE("sin_cos_turns is within 2^-23 of the double sine and cosine", "[ch07]") {
  double worst = 0.0;
  for (std::uint32_t m = 0; m < (1u << 24); m += 3) {
    const float turns = static_cast<float>(m) * 0x1p-24f;
    const SinCos sc = sin_cos_turns(turns);
    const double angle = 2.0 * std::numbers::pi * turns;
    worst = std::max(worst, std::abs(sc.sin - std::sin(angle)));
    worst = std::max(worst, std::abs(sc.cos - std::cos(angle)));
  }
  INFO("largest error " << worst);
  CHECK(worst <= 0x1p-23); // measured: 1.57 x 2^-24
  // The quarter turns are exact.
  CHECK(sin_cos_turns(0.0f).sin == 0.0f);
  CHECK(sin_cos_turns(0.0f).cos == 1.0f);
  CHECK(sin_cos_turns(0.25f).sin == 1.0f);
  CHECK(sin_cos_turns(0.25f).cos == 0.0f);
  CHECK(sin_cos_turns(0.5f).sin == 0.0f);
  CHECK(sin_cos_turns(0.5f).cos == -1.0f);
  CHECK(sin_cos_turns(0.75f).sin == -1.0f);
  CHECK(sin_cos_turns(0.75f).cos == 0.0f);
}

// ---------------------------------------------------------------------------------------------
// The camera.

TEST_CASE("the centre pixel of an odd-sized image looks along forward", "[ch07]") {
  const Vec3f eye{1.0f, 2.0f, 3.0f}, target{-4.0f, 0.5f, -2.0f};
  const PinholeCamera camera = make_protocol_camera(eye, target, 60.0f, 65, 49);
  const RayF ray = camera_ray(camera, 32, 24);
  const Vec3d forward = normalize_d(to_double(target) - to_double(eye));
  CHECK(distance_d(to_double(ray.direction), forward) < 1e-6);
  CHECK(same_bits(ray.direction, normalize(camera.basis.forward)));
}

TEST_CASE("camera rays follow the protocol's formula evaluated in double", "[ch07]") {
  struct Case {
    Vec3f eye, target;
    float vfov;
    int width, height;
  };
  const Case cases[] = {{{-300, 400, 300}, {1000, 100, -700}, 60.0f, 64, 48},
                        {{-14, 3, 0}, {10, 5, 0}, 60.0f, 1920, 1080},
                        {{0.1f, 0.2f, 5.0f}, {0, 0, 0}, 45.0f, 31, 77},
                        {{1e4f, -2e4f, 3e4f}, {1e4f, -2e4f, 3e4f + 1}, 170.0f, 5, 3}};
  for (const Case& c : cases) {
    CAPTURE(c.width, c.height, c.vfov);
    const PinholeCamera camera =
        make_protocol_camera(c.eye, c.target, c.vfov, c.width, c.height);
    const Vec3d forward = normalize_d(to_double(c.target) - to_double(c.eye));
    const Vec3d right = normalize_d(cross_d(forward, {0, 1, 0}));
    const Vec3d up = cross_d(right, forward);
    const double tan_half = std::tan(c.vfov * std::numbers::pi / 360.0);
    const double aspect = static_cast<double>(c.width) / c.height;
    const int columns[] = {0, c.width / 2, c.width - 1};
    const int rows[] = {0, c.height / 2, c.height - 1};
    for (int i : columns)
      for (int j : rows) {
        CAPTURE(i, j);
        const RayF ray = camera_ray(camera, i, j);
        const double sx = (2.0 * (i + 0.5) / c.width - 1.0) * tan_half * aspect;
        const double sy = (1.0 - 2.0 * (j + 0.5) / c.height) * tan_half;
        const Vec3d expected = normalize_d(right * sx + up * sy + forward);
        // Float rounding of a dozen steps, relative to the largest term (tan(85 deg) ~ 11).
        CHECK(distance_d(to_double(ray.direction), expected) < 1e-6 * (1.0 + tan_half));
        CHECK(std::abs(length(to_double(ray.direction)) - 1.0) < 1e-6);
        CHECK(same_bits(ray.origin, c.eye));
        CHECK(ray.tmin == 0.0f);
        CHECK(ray.tmax == k_inf);
      }
    // Pixel (0, 0) is the top-left corner: left of the centre and above it.
    const RayF corner = camera_ray(camera, 0, 0);
    CHECK(dot(to_double(corner.direction), right) < 0.0);
    CHECK(dot(to_double(corner.direction), up) > 0.0);
  }
}

TEST_CASE("camera_rays_cpu lists every pixel's ray row by row", "[ch07]") {
  const PinholeCamera camera = make_protocol_camera({0, 0, 5}, {0, 0, 0}, 45.0f, 7, 5);
  const std::vector<RayF> rays = camera_rays_cpu(camera);
  REQUIRE(rays.size() == 35);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 7; ++i) CHECK(same_bits(rays[j * 7 + i], camera_ray(camera, i, j)));
}

TEST_CASE("the camera refuses settings that make no rays", "[ch07]") {
  const Vec3f eye{0, 0, 0}, target{0, 0, -1};
  auto refuses = [](Vec3f e, Vec3f t, float fov, int w, int h, const std::string& why) {
    CAPTURE(why);
    CHECK_THAT(thrown_message<InputError>([&] { make_protocol_camera(e, t, fov, w, h); }),
               contains(why));
  };
  refuses(eye, eye, 45, 64, 48, "eye and target are the same point");
  refuses(eye, {0, 5, 0}, 45, 64, 48, "parallel to up");
  refuses(eye, {0, -5, 0}, 45, 64, 48, "parallel to up");
  refuses({0, 0, 0}, {0, 0, 0x1p-149f}, 45, 64, 48, "apart; the shortest supported");
  refuses(eye, target, 0, 64, 48, "between 0 and 180");
  refuses(eye, target, 180, 64, 48, "between 0 and 180");
  refuses(eye, target, -30, 64, 48, "between 0 and 180");
  refuses(eye, target, k_nan, 64, 48, "between 0 and 180");
  refuses(eye, target, 45, 0, 48, "image size 0x48");
  refuses(eye, target, 45, 64, -1, "image size 64x-1");
  refuses(eye, target, 45, k_max_image_side + 1, 48, "outside 1..16384");
  refuses({k_nan, 0, 0}, target, 45, 64, 48, "must be finite");
  refuses(eye, {0, k_inf, 0}, 45, 64, 48, "must be finite");
  refuses({-3e38f, 0, 0}, {3e38f, 0, 0}, 45, 64, 48, "must lie within +-1e+10");
  CHECK_NOTHROW(make_protocol_camera(eye, target, 45, 1, 1));
  CHECK_NOTHROW(make_protocol_camera(eye, target, 45, k_max_image_side, k_max_image_side));
}

// ---------------------------------------------------------------------------------------------
// Views.

TEST_CASE("auto-frame puts the bounding sphere exactly in the vertical field of view",
          "[ch07]") {
  Aabb box;
  box.grow(Vec3f{-1, -2, -3});
  box.grow(Vec3f{3, 2, 1});
  const float r = scene_radius(box);
  CHECK(r == static_cast<float>(0.5 * std::sqrt(48.0)));
  const ProtocolView view = auto_frame_view(box);
  CHECK(view.kind == ViewKind::auto_frame);
  CHECK(std::string(to_string(view.kind)) == "auto-frame");
  CHECK(view.vfov_degrees == 45.0f);
  CHECK(same_bits(view.target, Vec3f{1, 0, -1}));
  CHECK(view.eye.x == 1.0f);
  CHECK(view.eye.y == 0.0f);
  // Seen from the eye, the sphere of radius r about the centre spans exactly +-vfov/2.
  const double distance = view.eye.z - view.target.z;
  CHECK(std::asin(r / distance) * 360.0 / std::numbers::pi == Approx(45.0).epsilon(1e-6));
}

TEST_CASE("auto-frame refuses scenes with no size", "[ch07]") {
  CHECK(scene_radius(Aabb{}) == 0.0f);
  CHECK_THAT(thrown_message<InputError>([&] { auto_frame_view(Aabb{}); }),
             contains("no triangles"));
  Aabb point;
  point.grow(Vec3f{1, 2, 3});
  CHECK_THAT(thrown_message<InputError>([&] { auto_frame_view(point); }),
             contains("single point"));
  Aabb unbounded;
  unbounded.grow(Vec3f{0, 0, 0});
  unbounded.grow(Vec3f{k_inf, 0, 0});
  CHECK_THAT(thrown_message<InputError>([&] { auto_frame_view(unbounded); }),
             contains("not finite"));
}

TEST_CASE("the conference and sponza views are chosen by file name", "[ch07]") {
  Aabb box;
  box.grow(Vec3f{-1, -1, -1});
  box.grow(Vec3f{1, 1, 1});
  const ProtocolView conference = protocol_view("/data/models/conference.obj.gz", box);
  CHECK(conference.kind == ViewKind::conference);
  CHECK(same_bits(conference.eye, Vec3f{-300, 400, 300}));
  CHECK(same_bits(conference.target, Vec3f{1000, 100, -700}));
  CHECK(conference.vfov_degrees == 60.0f);
  const ProtocolView sponza = protocol_view("models/Sponza-Dabrovic.OBJ", box);
  CHECK(sponza.kind == ViewKind::sponza);
  CHECK(same_bits(sponza.eye, Vec3f{-14, 3, 0}));
  CHECK(same_bits(sponza.target, Vec3f{10, 5, 0}));
  CHECK(sponza.vfov_degrees == 60.0f);
  // Other objects are auto-framed; only the file's own name counts, not its folder's.
  CHECK(protocol_view("stanford-bunny.obj.gz", box).kind == ViewKind::auto_frame);
  CHECK(protocol_view("conference/bunny.obj", box).kind == ViewKind::auto_frame);
  CHECK(same_bits(protocol_view("dragon.obj", box).eye, auto_frame_view(box).eye));
}

// ---------------------------------------------------------------------------------------------
// Directions about a normal.

TEST_CASE("the Duff frame is orthonormal and right-handed for every normal", "[ch07]") {
  for (const Vec3f n : test_normals()) {
    CAPTURE(n.x, n.y, n.z);
    const TangentFrame frame = duff_frame(n);
    const Vec3d t = to_double(frame.tangent), b = to_double(frame.bitangent), nd = to_double(n);
    CHECK(std::abs(length(t) - 1.0) < 1e-6);
    CHECK(std::abs(length(b) - 1.0) < 1e-6);
    CHECK(std::abs(dot(t, b)) < 1e-6);
    CHECK(std::abs(dot(t, nd)) < 1e-6);
    CHECK(std::abs(dot(b, nd)) < 1e-6);
    CHECK(distance_d(cross_d(t, b), nd) < 2e-6);
  }
}

TEST_CASE("cosine directions are unit vectors in the normal's hemisphere", "[ch07]") {
  for (const Vec3f n : test_normals()) {
    CAPTURE(n.x, n.y, n.z);
    for (int k = 0; k < 64; ++k) {
      const Vec2f u = pcg2d_uniforms(k, 17);
      const Vec3f d = cosine_direction(n, u.x, u.y);
      REQUIRE(std::abs(length(to_double(d)) - 1.0) < 1e-6);
      REQUIRE(dot(d, n) > 0.0f);
    }
    // The extremes of u: straight along n, and the most grazing direction the hash can give.
    CHECK(distance_d(to_double(cosine_direction(n, 0.0f, 0.3f)), to_double(n)) < 1e-6);
    CHECK(dot(cosine_direction(n, 1.0f - 0x1p-24f, 0.7f), n) > 0.0f);
  }
}

TEST_CASE("cosine directions follow the cosine law", "[ch07]") {
  // With density cos(theta)/pi: E[cos] = 2/3, E[cos^2] = 1/2, and no preferred azimuth. A
  // uniform hemisphere would give E[cos] = 1/2. Standard errors over 100k samples are below
  // 0.002, the tolerances five times that.
  const Vec3f n = normalize(Vec3f{0.3f, -0.5f, 0.8f});
  const TangentFrame frame = duff_frame(n);
  double sum_cos = 0, sum_cos2 = 0, sum_t = 0, sum_b = 0;
  int samples = 0;
  for (int j = 0; j < 250; ++j)
    for (int i = 0; i < 400; ++i) {
      const Vec2f u = pcg2d_uniforms(i, j);
      const Vec3d d = to_double(cosine_direction(n, u.x, u.y));
      const double c = dot(d, to_double(n));
      sum_cos += c;
      sum_cos2 += c * c;
      sum_t += dot(d, to_double(frame.tangent));
      sum_b += dot(d, to_double(frame.bitangent));
      ++samples;
    }
  CHECK(sum_cos / samples == Approx(2.0 / 3.0).margin(0.004));
  CHECK(sum_cos2 / samples == Approx(0.5).margin(0.004));
  CHECK(sum_t / samples == Approx(0.0).margin(0.008));
  CHECK(sum_b / samples == Approx(0.0).margin(0.008));
}

// ---------------------------------------------------------------------------------------------
// The faced normal.

TEST_CASE("protocol_normal is the unit geometric normal on the ray's side", "[ch07]") {
  const TriangleF flat{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}; // counter-clockwise seen from +z
  CHECK(same_bits(protocol_normal(flat, {0, 0, -1}), Vec3f{0, 0, 1}));
  CHECK(same_bits(protocol_normal(flat, {0.3f, 0.2f, 1}), Vec3f{-0.0f, -0.0f, -1}));

  const TriangleF tilted{{1, 2, 3}, {-2, 0.5f, 4}, {0.5f, -1, -2}};
  const Vec3d geometric = normalize_d(cross_d(to_double(tilted.v1) - to_double(tilted.v0),
                                              to_double(tilted.v2) - to_double(tilted.v0)));
  for (const Vec3f d : test_normals()) {
    CAPTURE(d.x, d.y, d.z);
    const Vec3f n = protocol_normal(tilted, d);
    CHECK(std::abs(length(to_double(n)) - 1.0) < 1e-6);
    CHECK(dot(n, d) <= 0.0f);
    CHECK(std::abs(std::abs(dot(to_double(n), geometric)) - 1.0) < 1e-6);
  }
}

TEST_CASE("protocol_normal stays finite for tiny, huge and degenerate triangles", "[ch07]") {
  const Vec3f d = normalize(Vec3f{0.1f, 0.2f, -1});
  for (float scale : {1e-37f, 1e-30f, 1e-20f, 1e-12f, 1.0f, 1e12f, 1e20f, 1e30f, 1e37f}) {
    CAPTURE(scale);
    const TriangleF tri{{scale, 0, 0}, {2 * scale, 0, 0}, {scale, scale, 0}};
    const Vec3f n = protocol_normal(tri, d);
    CHECK(std::abs(length(to_double(n)) - 1.0) < 1e-6);
    CHECK(distance_d(to_double(n), {0, 0, 1}) < 1e-6);
  }
  // A segment has no plane: the normal turns back along the ray, still a unit vector.
  const TriangleF segment{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  CHECK(same_bits(protocol_normal(segment, d), -d));
  const TriangleF point{{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  CHECK(same_bits(protocol_normal(point, d), -d));
}

// ---------------------------------------------------------------------------------------------
// Secondary rays.

TEST_CASE("secondary rays start just off the hit surface and reach as far as their type says",
          "[ch07]") {
  const ch04::Mesh mesh = ch04::make_icosphere(2, {0.5, -0.25, 0.1}, 2.0);
  const float r = scene_radius(bounds_of(mesh));
  const Frame frame = trace_frame(mesh, {0.5f, 1.0f, 7.0f}, {0.5f, -0.25f, 0.1f}, 64, 48);
  const long long hit_pixels = count_hits(frame.hits);
  REQUIRE(hit_pixels > 300);
  REQUIRE(hit_pixels < 64 * 48); // misses too, so compaction has something to skip

  const SecondaryRays ao = secondary_rays_cpu(RayType::ao, mesh, frame.hits, frame.camera, r);
  const SecondaryRays diffuse =
      secondary_rays_cpu(RayType::diffuse, mesh, frame.hits, frame.camera, r);
  REQUIRE(static_cast<long long>(ao.rays.size()) == hit_pixels);
  REQUIRE(ao.pixel.size() == ao.rays.size());
  CHECK(ao.pixel == diffuse.pixel);
  CHECK(std::is_sorted(ao.pixel.begin(), ao.pixel.end()));
  CHECK(std::adjacent_find(ao.pixel.begin(), ao.pixel.end()) == ao.pixel.end());

  for (std::size_t k = 0; k < ao.rays.size(); ++k) {
    CAPTURE(k);
    const int p = ao.pixel[k];
    const MeshHit& hit = frame.hits[p];
    REQUIRE(hit.triangle >= 0);
    const RayF& ray = ao.rays[k];
    // ao and diffuse rays differ only in their reach.
    CHECK(same_bits(ray.origin, diffuse.rays[k].origin));
    CHECK(same_bits(ray.direction, diffuse.rays[k].direction));
    CHECK(ray.tmin == 0.0f);
    CHECK(diffuse.rays[k].tmin == 0.0f);
    CHECK(ray.tmax == 0.1f * r);
    CHECK(diffuse.rays[k].tmax == k_inf);
    // The origin lies 1e-4 r in front of the hit triangle, on the camera's side.
    const TriangleF tri = mesh.triangle(hit.triangle);
    Vec3d n = normalize_d(
        cross_d(to_double(tri.v1) - to_double(tri.v0), to_double(tri.v2) - to_double(tri.v0)));
    if (dot(n, to_double(frame.rays[p].direction)) > 0) n = -n;
    const double height = dot(to_double(ray.origin) - to_double(tri.v0), n);
    CHECK(height == Approx(1e-4 * r).epsilon(0.02));
    const Vec3d p_hit = to_double(frame.rays[p].origin) +
                        to_double(frame.rays[p].direction) * static_cast<double>(hit.t);
    CHECK(distance_d(to_double(ray.origin), p_hit + n * (1e-4 * r)) < 1e-5 * r);
    // Leaving into the camera's side of the surface.
    CHECK(std::abs(length(to_double(ray.direction)) - 1.0) < 1e-6);
    CHECK(dot(to_double(ray.direction), n) > 0.0);
  }
  // From the outside of a convex mesh, a ray leaving the surface never comes back to it.
  const std::vector<MeshHit> rehits =
      ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, diffuse.rays);
  CHECK(count_hits(rehits) == 0);
}

TEST_CASE("secondary rays from inside a closed mesh all hit it again", "[ch07]") {
  const ch04::Mesh mesh = ch04::make_icosphere(2, {0, 0, 0}, 1.0);
  const float r = scene_radius(bounds_of(mesh));
  const Frame frame = trace_frame(mesh, {0.1f, 0.2f, 0.3f}, {1, 0, 0}, 48, 32);
  REQUIRE(count_hits(frame.hits) == 48 * 32);
  const SecondaryRays diffuse =
      secondary_rays_cpu(RayType::diffuse, mesh, frame.hits, frame.camera, r);
  REQUIRE(diffuse.rays.size() == 48u * 32u);
  for (std::size_t k = 0; k < diffuse.pixel.size(); ++k) CHECK(diffuse.pixel[k] == int(k));
  const std::vector<MeshHit> hits =
      ch04::closest_hits_cpu(ch04::TriangleVariant::watertight, mesh, diffuse.rays);
  CHECK(count_hits(hits) == 48 * 32);
  // None re-hits the triangle it left (it starts in front of that plane, moving away).
  for (std::size_t k = 0; k < hits.size(); ++k) {
    CHECK(hits[k].t > 0.0f);
    CHECK(hits[k].triangle != frame.hits[diffuse.pixel[k]].triangle);
  }
}

TEST_CASE("secondary_rays_cpu refuses what it cannot make rays from", "[ch07]") {
  const ch04::Mesh mesh = ch04::make_icosphere(1, {0, 0, 0}, 1.0);
  const Frame frame = trace_frame(mesh, {0, 0, 4}, {0, 0, 0}, 16, 12);
  CHECK_THROWS_AS(secondary_rays_cpu(RayType::primary, mesh, frame.hits, frame.camera, 1.0f),
                  Error);
  const std::vector<MeshHit> short_buffer(frame.hits.begin(), frame.hits.end() - 1);
  CHECK_THAT(thrown_message<Error>([&] {
               secondary_rays_cpu(RayType::ao, mesh, short_buffer, frame.camera, 1.0f);
             }),
             contains("191 primary hits for 192 pixels"));
  std::vector<MeshHit> corrupt = frame.hits;
  corrupt[5] = {1.0f, static_cast<int>(mesh.triangles.size())};
  CHECK_THAT(thrown_message<Error>(
                 [&] { secondary_rays_cpu(RayType::ao, mesh, corrupt, frame.camera, 1.0f); }),
             contains("pixel 5 hit triangle 80 of a mesh of 80"));
}

TEST_CASE("scatter_to_pixels puts hits back at their pixels, misses elsewhere", "[ch07]") {
  const std::vector<MeshHit> hits = {{1.5f, 7}, {2.5f, 3}};
  const std::vector<int> pixel = {1, 4};
  const std::vector<MeshHit> image = scatter_to_pixels(hits, pixel, 6);
  REQUIRE(image.size() == 6);
  for (int p : {0, 2, 3, 5}) {
    CHECK(image[p].t == k_inf);
    CHECK(image[p].triangle == -1);
  }
  CHECK(same_bits(image[1], hits[0]));
  CHECK(same_bits(image[4], hits[1]));
  CHECK_THAT(thrown_message<Error>([&] { scatter_to_pixels(hits, std::vector<int>{1}, 6); }),
             contains("2 hits for 1 pixels"));
  CHECK_THAT(thrown_message<Error>([&] {
               scatter_to_pixels(hits, std::vector<int>{1, 6}, 6);
             }),
             contains("pixel 6 outside 0..5"));
  CHECK_THROWS_AS(scatter_to_pixels(hits, std::vector<int>{-1, 2}, 6), Error);
}

// ---------------------------------------------------------------------------------------------
// Ray files and hit files.

TEST_CASE("a ray file round-trips bit for bit", "[ch07]") {
  const std::vector<RayF> rays = {
      {{1, 2, 3}, {0, 0, -1}, 0.0f, k_inf},
      {{-0.0f, 1e-38f, -3e9f}, {0x1p-149f, -0.0f, 1}, -5.0f, -k_inf},
      {{0.1f, 0.2f, 0.3f}, {1, 1, 1}, 2.0f, 1.0f}, // tmin > tmax: valid, hits nothing
  };
  const TempFile file("round_trip.rays");
  write_ray_file(file.path, rays);
  CHECK(std::filesystem::file_size(file.path) == 3 * 32);
  CHECK(same_bits(read_ray_file(file.path), rays));
  // The layout is the documented one: the second float of the file is origin.y of ray 0.
  std::ifstream in(file.path, std::ios::binary);
  float first[8];
  in.read(reinterpret_cast<char*>(first), sizeof first);
  CHECK(first[1] == 2.0f);
  CHECK(first[5] == -1.0f);
  CHECK(first[7] == k_inf);
}

TEST_CASE("an empty ray file holds no rays", "[ch07]") {
  const TempFile file("empty.rays");
  write_ray_file(file.path, std::vector<RayF>{});
  CHECK(read_ray_file(file.path).empty());
}

TEST_CASE("malformed ray files are refused with the reason", "[ch07]") {
  const TempFile file("malformed.rays");
  auto refuses = [&](const std::vector<RayF>& rays, const std::string& why) {
    CAPTURE(why);
    write_ray_file(file.path, rays);
    CHECK_THAT(thrown_message<InputError>([&] { read_ray_file(file.path); }),
               contains(file.path + ": " + why));
  };
  const RayF good{{0, 0, 0}, {0, 0, 1}};
  auto bad = [&](auto change) {
    RayF ray = good;
    change(ray);
    return std::vector<RayF>{good, ray};
  };
  refuses(bad([](RayF& r) { r.origin.y = k_nan; }),
          "ray 1: the origin (0, nan, 0) is not finite");
  refuses(bad([](RayF& r) { r.origin.z = -k_inf; }), "ray 1: the origin (0, 0, -inf)");
  refuses(bad([](RayF& r) { r.direction.x = k_nan; }), "ray 1: the direction (nan, 0, 1)");
  refuses(bad([](RayF& r) { r.direction.z = k_inf; }), "ray 1: the direction (0, 0, inf)");
  refuses(bad([](RayF& r) { r.direction = {0, -0.0f, 0}; }), "ray 1: the direction is zero");
  refuses(bad([](RayF& r) { r.tmin = k_nan; }), "ray 1: tmin (nan) is not finite");
  refuses(bad([](RayF& r) { r.tmin = k_inf; }), "ray 1: tmin (inf) is not finite");
  refuses(bad([](RayF& r) { r.tmin = -k_inf; }), "ray 1: tmin (-inf) is not finite");
  refuses(bad([](RayF& r) { r.tmax = k_nan; }), "ray 1: tmax is NaN");

  const unsigned char bytes[100] = {};
  file.write_bytes(bytes, sizeof bytes);
  CHECK_THAT(
      thrown_message<InputError>([&] { read_ray_file(file.path); }),
      Catch::Matchers::Equals(file.path + ": 100 bytes is not a whole number of 32-byte rays"));
  write_ray_file(file.path, std::vector<RayF>(3, good));
  CHECK_THAT(thrown_message<InputError>([&] { read_ray_file(file.path, 2); }),
             contains(": 3 rays is more than the limit of 2"));
  CHECK(read_ray_file(file.path, 3).size() == 3);

  const std::string missing = file.path + ".missing";
  CHECK_THAT(thrown_message<InputError>([&] { read_ray_file(missing); }),
             contains(missing + ": cannot open"));
  const std::string folder = std::filesystem::temp_directory_path().string();
  CHECK_THAT(thrown_message<InputError>([&] { read_ray_file(folder); }),
             contains(": is a directory"));
}

TEST_CASE("a ray or hit file that cannot be written fails naming the path", "[ch07]") {
  const std::string path =
      (std::filesystem::temp_directory_path() / "rt_ch07_no_such_dir" / "out.rays").string();
  const std::vector<RayF> rays(2);
  CHECK_THAT(thrown_message<OutputError>([&] { write_ray_file(path, rays); }),
             contains(path + ": cannot write"));
  const std::vector<MeshHit> hits(2);
  CHECK_THAT(thrown_message<OutputError>([&] { write_hit_file(path, hits); }),
             contains(path + ": cannot write"));
  CHECK_FALSE(std::filesystem::exists(path));
}

TEST_CASE("a hit file round-trips, and malformed ones are refused", "[ch07]") {
  const TempFile file("hits.bin");
  const std::vector<MeshHit> hits = {{1.25f, 0}, {}, {3e38f, 123456}, {-2.0f, 7}};
  write_hit_file(file.path, hits);
  CHECK(std::filesystem::file_size(file.path) == 4 * 8);
  CHECK(same_bits(read_hit_file(file.path), hits));
  std::ifstream in(file.path, std::ios::binary);
  unsigned char record[8];
  in.read(reinterpret_cast<char*>(record), sizeof record);
  CHECK(record[4] == 0); // little-endian int32 0 after float32 1.25 (0x3fa00000)
  CHECK(record[3] == 0x3f);
  CHECK(record[2] == 0xa0);

  auto refuses = [&](const MeshHit& hit, const std::string& why) {
    CAPTURE(why);
    write_hit_file(file.path, std::vector<MeshHit>{{1.0f, 2}, hit});
    CHECK_THAT(thrown_message<InputError>([&] { read_hit_file(file.path); }),
               rt::testing::starts_with(file.path + ": record 1: ") && contains(why));
  };
  refuses({k_nan, 3}, "t is NaN");
  refuses({1.0f, -2}, "triangle id -2 is below -1");
  refuses({k_inf, 4}, "neither a hit nor a miss");
  refuses({2.0f, -1}, "neither a hit nor a miss");
  refuses({-k_inf, -1}, "neither a hit nor a miss");

  const unsigned char bytes[12] = {};
  file.write_bytes(bytes, sizeof bytes);
  CHECK_THAT(thrown_message<InputError>([&] { read_hit_file(file.path); }),
             Catch::Matchers::Equals(file.path +
                                     ": 12 bytes is not a whole number of 8-byte hit records"));
}

// ---------------------------------------------------------------------------------------------
// The GPU makes the same rays.

namespace {

struct DeviceMesh {
  DeviceBuffer<Vec3f> vertices;
  DeviceBuffer<ch04::IndexedTriangle> triangles;

  explicit DeviceMesh(const ch04::Mesh& mesh)
      : vertices(std::span<const Vec3f>(mesh.vertices)),
        triangles(std::span<const ch04::IndexedTriangle>(mesh.triangles)) {}
  ch04::MeshView view() const {
    return {vertices.data(), triangles.data(), static_cast<int>(triangles.size())};
  }
};

} // namespace

TEST_CASE("GPU camera rays equal the CPU's bit for bit", "[ch07][gpu]") {
  RT_REQUIRE_GPU();
  const PinholeCamera cameras[] = {
      make_protocol_camera({-300, 400, 300}, {1000, 100, -700}, 60.0f, 64, 48),
      make_protocol_camera({-14, 3, 0}, {10, 5, 0}, 60.0f, 67, 31),
      make_protocol_camera({0.1f, 0.2f, 5.0f}, {0, 0, 0}, 45.0f, 320, 180)};
  for (const PinholeCamera& camera : cameras) {
    CAPTURE(camera.width, camera.height);
    DeviceBuffer<RayF> d_rays(static_cast<std::size_t>(camera.width) * camera.height);
    d_rays.fill_bytes(0xff); // poisoned: a ray the kernel skips shows as NaN
    camera_rays_gpu(camera, d_rays.data());
    CHECK(same_bits(d_rays.to_host(), camera_rays_cpu(camera)));
  }
}

TEST_CASE("GPU secondary rays equal the CPU's bit for bit, in pixel order", "[ch07][gpu]") {
  RT_REQUIRE_GPU();
  const ch04::Mesh mesh = ch04::make_icosphere(3, {0.5, -0.25, 0.1}, 2.0);
  const float r = scene_radius(bounds_of(mesh));
  const DeviceMesh d_mesh(mesh);
  struct View {
    Vec3f eye, target;
    int width, height;
  };
  const View views[] = {{{0.5f, 1.0f, 7.0f}, {0.5f, -0.25f, 0.1f}, 64, 48},   // some misses
                        {{0.6f, -0.1f, 0.3f}, {3.0f, 1.0f, -1.0f}, 128, 96}}; // all hit
  for (const View& v : views) {
    const Frame frame = trace_frame(mesh, v.eye, v.target, v.width, v.height);
    const std::size_t pixel_count = frame.hits.size();
    const DeviceBuffer<MeshHit> d_hits{std::span<const MeshHit>(frame.hits)};
    for (RayType type : {RayType::ao, RayType::diffuse}) {
      CAPTURE(v.width, v.height, to_string(type));
      const SecondaryRays cpu = secondary_rays_cpu(type, mesh, frame.hits, frame.camera, r);
      REQUIRE(!cpu.rays.empty());
      DeviceBuffer<RayF> d_rays(pixel_count);
      DeviceBuffer<int> d_pixels(pixel_count);
      d_rays.fill_bytes(0xff);
      d_pixels.fill_bytes(0xff);
      const int count = secondary_rays_gpu(type, d_mesh.view(), d_hits.data(), frame.camera, r,
                                           d_rays.data(), d_pixels.data());
      REQUIRE(count == static_cast<int>(cpu.rays.size()));
      std::vector<RayF> rays = d_rays.to_host();
      std::vector<int> pixels = d_pixels.to_host();
      rays.resize(count);
      pixels.resize(count);
      CHECK(pixels == cpu.pixel);
      long long differing = 0;
      for (int k = 0; k < count; ++k) differing += same_bits(rays[k], cpu.rays[k]) ? 0 : 1;
      CHECK(differing == 0);
    }
  }
}

TEST_CASE("GPU secondary rays refuse primary and skip corrupt triangle ids", "[ch07][gpu]") {
  RT_REQUIRE_GPU();
  const ch04::Mesh mesh = ch04::make_icosphere(1, {0, 0, 0}, 1.0);
  const DeviceMesh d_mesh(mesh);
  const PinholeCamera camera = make_protocol_camera({0, 0, 0.2f}, {0, 0, -1}, 60.0f, 4, 2);
  std::vector<MeshHit> hits(8, MeshHit{});
  hits[2] = {0.9f, 3};
  hits[5] = {0.8f, static_cast<int>(mesh.triangles.size())}; // outside the mesh
  hits[7] = {0.9f, 79};
  const DeviceBuffer<MeshHit> d_hits{std::span<const MeshHit>(hits)};
  DeviceBuffer<RayF> d_rays(8);
  DeviceBuffer<int> d_pixels(8);
  CHECK_THROWS_AS(secondary_rays_gpu(RayType::primary, d_mesh.view(), d_hits.data(), camera,
                                     1.0f, d_rays.data(), d_pixels.data()),
                  Error);
  const int count = secondary_rays_gpu(RayType::ao, d_mesh.view(), d_hits.data(), camera, 1.0f,
                                       d_rays.data(), d_pixels.data());
  REQUIRE(count == 2);
  const std::vector<int> pixels = d_pixels.to_host();
  CHECK(pixels[0] == 2);
  CHECK(pixels[1] == 7);
}
