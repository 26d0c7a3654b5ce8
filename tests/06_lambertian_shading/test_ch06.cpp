// Chapter 06 tests on the CPU: Lambert's law on a plane at known angles, a sphere under a
// head-on light, two-sided surfaces, vertex normals (computed, from the file, and the
// fallbacks when they have no direction), shadows (no acne at any scale, real occluders),
// specialised kernels against the all-features one, and the program's handling of bad input.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "image_files.h"
#include "run_program.h"
#include "shading_cases.h"

#include "obj_loader.h"
#include "rt/error.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "vertex_normals.h"

using namespace rt;
using namespace rt::ch06;
using rt::testing::records_differing;
using rt::testing::render_cpu;
using rt::testing::ShadedFrame;

namespace {

constexpr Vec3f k_albedo{0.5f, 0.25f, 0.75f};

// A scene from a mesh in palette slot 1 (k_albedo), with computed vertex normals, lit by one
// directional light towards `to_light` of radiance 1 and an ambient term.
ShadedScene scene_of(const ch04::Mesh& mesh, Vec3f to_light, float ambient) {
  ShadedScene scene;
  scene.mesh = mesh;
  scene.material.assign(mesh.triangles.size(), 1);
  scene.palette.albedo[1] = k_albedo;
  scene.normals = compute_vertex_normals(mesh);
  scene.lights.ambient = {ambient, ambient, ambient};
  scene.lights.directional_count = 1;
  scene.lights.directional[0] = {to_light, {1.0f, 1.0f, 1.0f}};
  return scene;
}

// The square [-1, 1]^2 of the plane z = 0, two triangles facing +z.
ch04::Mesh unit_square() {
  ch04::Mesh mesh;
  mesh.vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

// Shades one ray with the kernel of every kind for `features`, in precision T, and checks that
// all of them give the same sample; returns it.
template <class T>
ShadedSample<T> shade(const ShadedScene& scene, unsigned features, Vec3d origin,
                      Vec3d direction) {
  const ch03::Ray<T> ray{origin.as<T>(), direction.as<T>()};
  const ShadedSample<T> generic =
      shade_ray(host_view(scene, k_all_features), ray, AllFeatures{features});
  const ShadedSample<T> specialised = with_specialised(features, [&](auto kernel) {
    return shade_ray(host_view(scene, features), ray, kernel);
  });
  CHECK(specialised.colour == generic.colour);
  CHECK(specialised.triangle == generic.triangle);
  CHECK(specialised.shadow_rays == generic.shadow_rays);
  return specialised;
}

bool finite(Vec3f c) { return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z); }

} // namespace

TEST_CASE("a plane under a directional light: albedo times (ambient + cos theta)", "[ch06]") {
  constexpr float k_ambient = 0.125f;
  for (const double degrees : {0.0, 30.0, 45.0, 60.0, 85.0, 90.0, 120.0, 180.0}) {
    const double theta = degrees * std::numbers::pi / 180.0;
    const Vec3f to_light = Vec3d{std::sin(theta), 0.0, std::cos(theta)}.as<float>();
    const ShadedScene scene = scene_of(unit_square(), to_light, k_ambient);
    // Lambert's law with every product rounded as the shader rounds it: n = (0, 0, 1) exactly,
    // so cos theta is the light direction's z, and a light behind the plane adds nothing.
    const float cosine = to_light.z > 0.0f ? to_light.z : 0.0f;
    const Vec3f expected = k_albedo * (k_ambient + cosine);
    for (const unsigned features : {0u, unsigned(k_smooth_normals), unsigned(k_shadows),
                                    unsigned(k_smooth_normals | k_shadows)}) {
      CAPTURE(degrees, features);
      const ShadedSample<float> hit = shade<float>(scene, features, {0.3, 0.2, 5}, {0, 0, -1});
      REQUIRE(hit.triangle >= 0);
      CHECK(hit.colour == expected);
      const double exact_cos = std::max(std::cos(theta), 0.0);
      CHECK(hit.colour.y == Approx(0.25 * (0.125 + exact_cos)).margin(1e-7));
      CHECK(hit.shadowed_facing == 0);
      const ShadedSample<double> reference =
          shade<double>(scene, features, {0.3, 0.2, 5}, {0, 0, -1});
      CHECK(reference.colour.y == Approx(0.25 * (0.125 + double(cosine))).epsilon(1e-15));
    }
  }
}

TEST_CASE("two-sided: a plane seen from behind is lit from behind, not through", "[ch06]") {
  constexpr float k_ambient = 0.125f;
  const Vec3f below = normalize(Vec3f{0.3f, 0.0f, -1.0f});
  for (const unsigned features : {0u, unsigned(k_smooth_normals | k_shadows)}) {
    CAPTURE(features);
    // Viewer and light both below: the back face is lit like a front face.
    const ShadedScene lit = scene_of(unit_square(), below, k_ambient);
    const ShadedSample<float> back = shade<float>(lit, features, {0.3, 0.2, -5}, {0, 0, 1});
    CHECK(back.colour == k_albedo * (k_ambient + (-below.z)));
    CHECK(back.shadow_rays == ((features & k_shadows) ? 1 : 0));
    // Viewer below, light above: the side the viewer sees gets only the ambient term.
    const ShadedScene away = scene_of(unit_square(), -below, k_ambient);
    CHECK(shade<float>(away, features, {0.3, 0.2, -5}, {0, 0, 1}).colour ==
          k_albedo * k_ambient);
  }
}

TEST_CASE("a sphere under a head-on light: brightest at the centre, cosine falloff", "[ch06]") {
  const ShadedScene scene =
      scene_of(ch04::make_icosphere(4, {0, 0, 0}, 1.0), {0.0f, 0.0f, 1.0f}, 0.0f);
  for (const unsigned features : {unsigned(k_smooth_normals), 0u}) {
    // Parallel rays down -z: at distance r from the axis the sphere's normal makes
    // cos = sqrt(1 - r^2) with the light. Smooth normals follow it closely; faces only
    // roughly.
    const double tolerance = features == 0 ? 0.05 : 0.01;
    double previous = 2.0;
    for (int step = 0; step <= 9; ++step) {
      const double r = 0.1 * step;
      const ShadedSample<float> hit = shade<float>(scene, features, {r, 0.0, 5.0}, {0, 0, -1});
      const double cosine = hit.colour.x / k_albedo.x;
      CAPTURE(features, r, cosine);
      REQUIRE(hit.triangle >= 0);
      CHECK(cosine == Approx(std::sqrt(1 - r * r)).margin(tolerance));
      if (features != 0) CHECK(cosine < previous); // falls off monotonically
      previous = cosine;
    }
  }
  // The centre is the brightest point of the image.
  CameraSpec spec;
  spec.eye = {0, 0, 5};
  spec.target = {0, 0, 0};
  spec.kind = ch03::CameraKind::orthographic;
  const Extent extent{41, 41};
  const ShadedFrame frame =
      render_cpu(scene, KernelKind::specialised, k_smooth_normals, spec, extent);
  int brightest = 0;
  for (std::size_t i = 0; i < frame.image.pixels.size(); ++i)
    if (frame.records[i].triangle >= 0)
      brightest = std::max<int>(brightest, frame.image.pixels[i].r);
  CHECK(frame.image.at(20, 20).r == brightest);
}

TEST_CASE("computed vertex normals: unit, radial on a sphere, angle weighting is symmetric",
          "[ch06]") {
  const ch04::Mesh box = ch04::make_box({-1, -1, -1}, {1, 1, 1}, 1);
  const std::vector<Vec3f> by_angle = compute_vertex_normals(box, NormalWeighting::angle);
  const std::vector<Vec3f> by_area = compute_vertex_normals(box, NormalWeighting::area);
  REQUIRE(by_angle.size() == box.vertices.size());
  double largest_tilt = 0.0;
  for (std::size_t i = 0; i < box.vertices.size(); ++i) {
    // A cube's corner: three faces at right angles, whichever way each face was split.
    const Vec3f corner_direction = box.vertices[i] * (1.0f / std::sqrt(3.0f));
    CAPTURE(i);
    CHECK(length(by_angle[i]) == Approx(1.0).epsilon(1e-6));
    CHECK(length(by_area[i]) == Approx(1.0).epsilon(1e-6));
    CHECK(length(by_angle[i] - corner_direction) < 1e-6f);
    largest_tilt = std::max(largest_tilt, double(length(by_area[i] - corner_direction)));
  }
  // Area weighting counts a face split into two triangles at a corner twice.
  CHECK(largest_tilt > 0.1);

  const ch04::Mesh sphere = ch04::make_icosphere(3, {1, 2, 3}, 2.0);
  const std::vector<Vec3f> normals = compute_vertex_normals(sphere);
  for (std::size_t i = 0; i < sphere.vertices.size(); ++i) {
    const Vec3f radial = normalize(sphere.vertices[i] - Vec3f{1, 2, 3});
    CAPTURE(i);
    CHECK(length(normals[i]) == Approx(1.0).epsilon(1e-6));
    CHECK(dot(normals[i], radial) > 0.9999f);
  }

  // Slivers add nothing; a vertex without a real triangle gets no direction at all.
  ch04::Mesh slivers;
  slivers.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {5, 5, 5}};
  slivers.triangles = {{0, 1, 2}, {0, 1, 3}, {3, 3, 4}};
  const std::vector<Vec3f> few = compute_vertex_normals(slivers);
  CHECK(few[0] == Vec3f{0, 0, 1});
  CHECK(few[1] == Vec3f{0, 0, 1});
  CHECK(few[3] == Vec3f{0, 0, 0});
  CHECK(few[4] == Vec3f{0, 0, 0});
}

TEST_CASE("a zero-length interpolated normal falls back to the face's: no NaN", "[ch06]") {
  // Corner normals +z, -z, +z: at u = 1/2, v = 1/4 they blend to exactly zero.
  ch04::Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  const Vec3f to_light = normalize(Vec3f{0.2f, 0.3f, 1.0f});
  ShadedScene cancelling = scene_of(mesh, to_light, 0.125f);
  cancelling.normals = {{0, 0, 1}, {0, 0, -1}, {0, 0, 1}};
  ShadedScene zero = cancelling; // normals with no direction at all, or not even numbers
  zero.normals = {{0, 0, 0}, {0, 0, 0}, {NAN, 0, 1}};
  const Vec3f face_lit = k_albedo * (0.125f + to_light.z);
  for (const unsigned features : {unsigned(k_smooth_normals), k_all_features}) {
    CAPTURE(features);
    CHECK(shade<float>(cancelling, features, {0.5, 0.25, 2}, {0, 0, -1}).colour == face_lit);
    CHECK(shade<double>(cancelling, features, {0.5, 0.25, 2}, {0, 0, -1}).colour.x ==
          Approx(0.5 * (0.125 + double(to_light.z))).epsilon(1e-7));
    CHECK(shade<float>(zero, features, {0.3, 0.3, 2}, {0, 0, -1}).colour == face_lit);
    // Everywhere on the triangle, from either side: finite colours.
    for (int i = 0; i < 20; ++i) {
      for (int j = 0; i + j < 20; ++j) {
        for (const double side : {2.0, -2.0}) {
          const Vec3d origin{(i + 0.25) / 20, (j + 0.25) / 20, side};
          const Vec3d direction{0.01 * i, -0.02 * j, -side};
          CAPTURE(i, j, side);
          CHECK(finite(shade<float>(cancelling, features, origin, direction).colour));
          CHECK(finite(shade<float>(zero, features, origin, direction).colour));
        }
      }
    }
  }
}

TEST_CASE("a sliver the watertight test hits but that has no float normal faces the viewer",
          "[ch06]") {
  // Three collinear points: chapter 04 shows the watertight test can accept such a sliver.
  ch04::Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 1, 0}, {2, 2, 0}};
  mesh.triangles = {{0, 1, 2}};
  const ShadedScene scene = scene_of(mesh, {0, 0, 1}, 0.125f);
  const SceneView view = host_view(scene, k_all_features);
  const ch03::Ray<float> ray{{1, 1, 3}, {0, 0, -1}};
  const SurfaceHit<float> hit{3.0f, 0, 0.5f, 0.0f}; // as if the test had accepted it
  const ShadingPoint<float> point = shading_point(view, ray, hit, AllFeatures{k_all_features});
  CHECK(point.geometric == Vec3f{0, 0, 1});
  CHECK(finite(point.shading));
  CHECK(finite(point.shadow_from));
}

TEST_CASE("the file's normals are used where it has them, computed ones elsewhere", "[ch06]") {
  // Two triangles of the plane z = 0: the first with a tilted normal from the file, the
  // second with none (its corners get the computed normal, +z).
  const ch05::ObjMesh obj = ch05::parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                            "vn 0.6 0 0.8\n"
                                            "f 1//1 2//1 3//1\nf 1 3 4\n",
                                            "tilted.obj");
  ShadedScene scene = scene_from_obj(obj, LightSettings{});
  CHECK_THAT(scene.description, rt::testing::contains("from the file (3 corners without"));
  scene.lights.ambient = {0.125f, 0.125f, 0.125f};
  scene.lights.directional[0] = {{0, 0, 1}, {1, 1, 1}};
  scene.lights.point_count = 0;
  const Vec3f albedo = scene.palette.albedo[0]; // no material: slot 0
  for (const unsigned features : {unsigned(k_smooth_normals), k_all_features}) {
    CAPTURE(features);
    const ShadedSample<float> tilted = shade<float>(scene, features, {0.7, 0.2, 2}, {0, 0, -1});
    CHECK(tilted.triangle == 0);
    CHECK(tilted.colour.x == Approx(albedo.x * (0.125f + 0.8f)).epsilon(1e-6));
    const ShadedSample<float> plain = shade<float>(scene, features, {0.2, 0.7, 2}, {0, 0, -1});
    CHECK(plain.triangle == 1);
    CHECK(plain.colour == albedo * (0.125f + 1.0f));
  }
  // Flat shading ignores the file's normals: both triangles face the light squarely.
  CHECK(shade<float>(scene, 0, {0.7, 0.2, 2}, {0, 0, -1}).colour == albedo * 1.125f);

  // A file without normals: one computed normal per position, indexed by the triangles, so
  // no second index array exists (nor is uploaded).
  const ShadedScene computed = scene_from_obj(
      ch05::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "plain.obj"), LightSettings{});
  CHECK(computed.normal_indices.empty());
  CHECK(computed.normals == std::vector<Vec3f>(3, Vec3f{0, 0, 1}));
  CHECK_THAT(computed.description, rt::testing::contains("computed (angle-weighted)"));
}

TEST_CASE("smooth shading of a loaded model with vn follows the file's normals", "[ch06]") {
  // An octahedron whose file normals are the exact sphere normals at its vertices: smooth
  // shading must use them (flat shading gives one value per face).
  std::string text;
  const char* axes[] = {"1 0 0", "-1 0 0", "0 1 0", "0 -1 0", "0 0 1", "0 0 -1"};
  for (const char* a : axes) text += std::string("v ") + a + "\nvn " + a + "\n";
  const int faces[8][3] = {{1, 3, 5}, {3, 2, 5}, {2, 4, 5}, {4, 1, 5},
                           {3, 1, 6}, {2, 3, 6}, {4, 2, 6}, {1, 4, 6}};
  for (const auto& f : faces)
    text += "f " + std::to_string(f[0]) + "//" + std::to_string(f[0]) + " " +
            std::to_string(f[1]) + "//" + std::to_string(f[1]) + " " + std::to_string(f[2]) +
            "//" + std::to_string(f[2]) + "\n";
  ShadedScene scene = scene_from_obj(ch05::parse_obj(text, "octahedron.obj"), LightSettings{});
  scene.lights.ambient = {};
  scene.lights.directional[0] = {{0, 0, 1}, {1, 1, 1}};
  scene.lights.point_count = 0;
  const float albedo = scene.palette.albedo[0].x;
  // Down the z axis onto the +z vertex's face region: barycentric blends of (0,0,1) with the
  // x and y axes. At the centre of face 1 the blend is (1, 1, 1) / 3: cos = 1/sqrt(3).
  const Vec3d centre{1.0 / 3, 1.0 / 3, 1.0 / 3};
  const ShadedSample<float> smooth =
      shade<float>(scene, k_smooth_normals, centre + Vec3d{0, 0, 4}, {0, 0, -1});
  CHECK(smooth.colour.x == Approx(albedo / std::sqrt(3.0)).epsilon(1e-5));
  // Near the +z vertex the smooth normal is nearly (0, 0, 1); the face's stays (1,1,1)/sqrt 3.
  const ShadedSample<float> near_top =
      shade<float>(scene, k_smooth_normals, {0.01, 0.01, 4}, {0, 0, -1});
  const ShadedSample<float> flat = shade<float>(scene, 0, {0.01, 0.01, 4}, {0, 0, -1});
  CHECK(near_top.colour.x > 0.99f * albedo);
  CHECK(flat.colour.x == Approx(albedo / std::sqrt(3.0)).epsilon(1e-5));
}

TEST_CASE("no shadow acne on a convex mesh at scales 1, 1e3 and 1e6", "[ch06]") {
  const Extent extent{96, 64};
  for (const double scale : {1.0, 1e3, 1e6}) {
    const ShadedScene sphere = make_lone_sphere(3, scale, LightSettings{});
    const CameraSpec spec = frame_bounds_down_z(bounds_of(sphere.mesh), 40.0, extent);
    for (const bool smooth : {false, true}) {
      const unsigned features = features_used(sphere, smooth, true);
      REQUIRE(features == ((smooth ? k_smooth_normals : 0u) | k_shadows | k_point_lights));
      const ShadedFrame frame =
          render_cpu(sphere, KernelKind::specialised, features, spec, extent);
      long long rays = 0, acne = 0, hits = 0;
      for (const ShadedPixelRecord& r : frame.records) {
        rays += r.shadow_rays;
        acne += r.shadowed_facing;
        hits += r.triangle >= 0;
        CHECK(r.nan == 0);
      }
      CAPTURE(scale, smooth, rays, hits);
      CHECK(hits > 500);
      CHECK(rays > 500);
      CHECK(acne == 0);
    }
  }
}

TEST_CASE("the shadow terminator: lifted shadow origins light a coarse sphere's smooth side",
          "[ch06]") {
  // An 80-triangle sphere lit from the side: along the terminator, the smooth normal still
  // faces the light while shadow rays from the flat triangles run into their neighbours.
  const Extent extent{160, 90};
  LightSettings side;
  side.direction = {1.0, 0.2, 0.0};
  side.point_light = false;
  ShadedScene sphere = make_lone_sphere(1, 1.0, side);
  const CameraSpec spec = frame_bounds_down_z(bounds_of(sphere.mesh), 40.0, extent);
  const unsigned features = features_used(sphere, true, true);
  const ShadedFrame lifted =
      render_cpu(sphere, KernelKind::specialised, features, spec, extent);
  sphere.lift_shadow_origins = false;
  const ShadedFrame unlifted =
      render_cpu(sphere, KernelKind::specialised, features, spec, extent);
  long long brighter = 0, darker = 0;
  for (std::size_t i = 0; i < lifted.image.pixels.size(); ++i) {
    const Rgba8 a = lifted.image.pixels[i], b = unlifted.image.pixels[i];
    const int sum_lifted = a.r + a.g + a.b, sum_unlifted = b.r + b.g + b.b;
    brighter += sum_lifted > sum_unlifted;
    darker += sum_lifted < sum_unlifted;
  }
  CAPTURE(brighter, darker);
  CHECK(brighter > 20);
  CHECK(darker == 0);
}

TEST_CASE("a real occluder shadows: a box over a floor, directional and point lights",
          "[ch06]") {
  ch04::Mesh mesh = ch04::make_box({-1, 1, -1}, {1, 2, 1}, 1);
  const int base = static_cast<int>(mesh.vertices.size());
  for (const Vec3f corner :
       {Vec3f{-5, 0, -5}, Vec3f{5, 0, -5}, Vec3f{5, 0, 5}, Vec3f{-5, 0, 5}})
    mesh.vertices.push_back(corner);
  mesh.triangles.push_back({base, base + 2, base + 1});
  mesh.triangles.push_back({base, base + 3, base + 2});
  ShadedScene scene = scene_of(mesh, {0, 1, 0}, 0.125f);
  const Vec3d under{0, 0.5, 5}, beside{3, 0.5, 5};
  const Vec3d to_floor_under = Vec3d{0, 0, 0} - under,
              to_floor_beside = Vec3d{3, 0, 0} - beside;
  for (const unsigned features : {unsigned(k_shadows), k_all_features}) {
    CAPTURE(features);
    const ShadedSample<float> shadowed = shade<float>(scene, features, under, to_floor_under);
    CHECK(shadowed.colour == k_albedo * 0.125f);
    CHECK(shadowed.shadow_rays == 1);
    CHECK(shadowed.shadowed_facing == 1);
    const ShadedSample<float> lit = shade<float>(scene, features, beside, to_floor_beside);
    CHECK(lit.colour == k_albedo * 1.125f);
    CHECK(lit.shadowed_facing == 0);
  }
  // Without shadow rays the box casts nothing.
  CHECK(shade<float>(scene, 0, under, to_floor_under).colour == k_albedo * 1.125f);

  // A point light: above the box it is blocked; between the floor and the box it is not (the
  // shadow ray ends at the light).
  scene.lights.directional_count = 0;
  scene.lights.point_count = 1;
  for (const float height : {5.0f, 0.5f}) {
    scene.lights.point[0] = {{0, height, 0}, {1, 1, 1}};
    CAPTURE(height);
    const ShadedSample<float> hit = shade<float>(scene, k_all_features, under, to_floor_under);
    const Vec3f lit = k_albedo * (0.125f + 1.0f / (height * height));
    if (height > 2)
      CHECK(hit.colour == k_albedo * 0.125f);
    else
      CHECK(hit.colour.x == Approx(lit.x).epsilon(1e-6));
  }
}

TEST_CASE("specialised kernels and the all-features kernel give identical frames", "[ch06]") {
  const ShadedScene scene = make_default_scene(1, 1.0, LightSettings{});
  const CameraSpec spec = default_camera(1.0);
  const Extent extent{64, 36};
  for (unsigned features = 0; features <= k_all_features; ++features) {
    CAPTURE(features, describe_features(features));
    // The specialised kernel gets only the arrays its features read: a flat one reads no
    // normals (null pointers here), or this test would crash.
    const ShadedFrame specialised =
        render_cpu(scene, KernelKind::specialised, features, spec, extent);
    const ShadedFrame generic =
        render_cpu(scene, KernelKind::all_features, features, spec, extent);
    CHECK(count_differing_pixels(specialised.image.pixels, generic.image.pixels) == 0);
    CHECK(records_differing(specialised.records, generic.records) == 0);
  }
}

TEST_CASE("frames against the float64 reference: close, and no NaN", "[ch06]") {
  const ShadedScene scene = make_default_scene(1, 1.0, LightSettings{});
  const CameraSpec spec = default_camera(1.0);
  const Extent extent{80, 45};
  for (const bool smooth : {false, true}) {
    for (const bool shadows : {false, true}) {
      const unsigned features = features_used(scene, smooth, shadows);
      const ShadedFrame frame =
          render_cpu(scene, KernelKind::specialised, features, spec, extent);
      const ShadedReference reference = render_shaded_reference(scene, features, spec, extent);
      const ShadedFrameError e =
          compare_with_reference(frame.image, frame.records, reference.image);
      CAPTURE(smooth, shadows, e.pixels_differing, e.rmse);
      CHECK(e.nan_pixels == 0);
      CHECK(e.pixels_differing <= extent.pixel_count() / 100);
      CHECK(e.rmse < 1.0);
      // A cosine at 0 or a grazing shadow ray may go the other way in double.
      const long long reference_shadow_rays = reference.rays - extent.pixel_count();
      if (shadows)
        CHECK(std::abs(e.shadow_rays - reference_shadow_rays) <= extent.pixel_count() / 100);
      else
        CHECK((e.shadow_rays == 0 && reference_shadow_rays == 0));
    }
  }
}

TEST_CASE("scene bytes: flat shading reads no normals, the all-features kernel all", "[ch06]") {
  const ShadedScene scene = make_default_scene(2, 1.0, LightSettings{});
  const std::size_t triangles = scene.mesh.triangles.size();
  const std::size_t geometry = scene.mesh.vertices.size() * 12 + triangles * 12 + triangles;
  const std::size_t normals = scene.normals.size() * 12 + scene.normal_indices.size() * 12;
  CHECK(scene_bytes(scene, 0) == geometry);
  CHECK(scene_bytes(scene, k_shadows | k_point_lights) == geometry);
  CHECK(scene_bytes(scene, k_smooth_normals) == geometry + normals);
  CHECK(scene_bytes(scene, uploaded_features(KernelKind::all_features, 0)) ==
        geometry + normals);
  const SceneView flat = host_view(scene, k_shadows);
  CHECK(flat.normals == nullptr);
  CHECK(flat.normal_indices == nullptr);
}

TEST_CASE("the features a frame uses", "[ch06]") {
  ShadedScene scene = make_default_scene(0, 1.0, LightSettings{});
  CHECK(features_used(scene, true, true) == k_all_features);
  CHECK(features_used(scene, false, false) == k_point_lights);
  LightSettings no_point;
  no_point.point_light = false;
  scene = make_default_scene(0, 1.0, no_point);
  CHECK(features_used(scene, true, true) == (k_smooth_normals | k_shadows));
  scene.lights.directional_count = 0; // nothing to cast a shadow from
  CHECK(features_used(scene, false, true) == 0);
  CHECK(describe_features(k_all_features) == "smooth normals, shadows, point lights");
  CHECK(describe_features(0) == "none");
}

TEST_CASE("the built-in scene: sphere smooth, box and floor faceted, all normals unit",
          "[ch06]") {
  const ShadedScene scene = make_default_scene(2, 1.0, LightSettings{});
  CHECK(scene.mesh.triangles.size() == 320 + 48 + 2);
  REQUIRE(scene.normal_indices.size() == scene.mesh.triangles.size());
  REQUIRE(scene.material.size() == scene.mesh.triangles.size());
  CHECK(scene.normals.size() == 162 + 6 + 1); // sphere vertices, box faces, floor
  for (const Vec3f& n : scene.normals) CHECK(length(n) == Approx(1.0).epsilon(1e-6));
  CHECK(scene.lights.directional_count == 1);
  CHECK(scene.lights.point_count == 1);
  // Scaled, the lights move with it and light the same way.
  const ShadedScene big = make_default_scene(2, 1e6, LightSettings{});
  CHECK(big.lights.point[0].position.y == Approx(1e6 * scene.lights.point[0].position.y));
  CHECK(big.lights.point[0].intensity.x == Approx(1e12 * scene.lights.point[0].intensity.x));
}

TEST_CASE("auto-framing: the bounding sphere fills the narrower side of the view", "[ch06]") {
  ch04::Mesh mesh = ch04::make_box({1, 2, 3}, {3, 4, 5}, 1);
  const Bounds bounds = bounds_of(mesh);
  CHECK(bounds.min == Vec3d{1, 2, 3});
  CHECK(bounds.max == Vec3d{3, 4, 5});
  // A wide image: the vertical field of view is the narrower one.
  const CameraSpec wide = frame_bounds_down_z(bounds, 45.0, {160, 90});
  CHECK(wide.target == Vec3d{2, 3, 4});
  const double distance = std::sqrt(3.0) / std::sin(22.5 * std::numbers::pi / 180.0);
  CHECK(wide.eye.x == 2.0);
  CHECK(wide.eye.y == 3.0);
  CHECK(wide.eye.z == Approx(4.0 + distance).epsilon(1e-12));
  // A tall image: the horizontal one, tan(h) = tan(22.5 deg) * 90 / 160; the sphere touches
  // the left and right edges instead of being cut off by them.
  const CameraSpec tall = frame_bounds_down_z(bounds, 45.0, {90, 160});
  const double half_horizontal =
      std::atan(std::tan(22.5 * std::numbers::pi / 180.0) * 90.0 / 160.0);
  CHECK(tall.eye.z == Approx(4.0 + std::sqrt(3.0) / std::sin(half_horizontal)).epsilon(1e-12));
  CHECK(tall.eye.z > wide.eye.z);
  CHECK_THROWS_AS(bounds_of(ch04::Mesh{}), InputError);
}

TEST_CASE("light settings are checked", "[ch06]") {
  LightSettings settings;
  CHECK_NOTHROW(validate_lights(settings));
  settings.direction = {0, 0, 0};
  CHECK_THROWS_AS(validate_lights(settings), UsageError);
  settings.direction = {NAN, 1, 0};
  CHECK_THROWS_AS(validate_lights(settings), UsageError);
  settings = {};
  settings.ambient = 1.5;
  CHECK_THROWS_AS(validate_lights(settings), UsageError);
}

namespace {

using rt::testing::ProgramRun;

const rt::testing::HeadlessCpuProgram run_program(RT_CH06_PROGRAM);

} // namespace

TEST_CASE("program: bad input gives one error line and a non-zero exit", "[ch06]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch06");
  const std::string broken = (folder / "broken.obj").string();
  std::ofstream(broken) << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
  const std::string good = (folder / "good.obj").string();
  std::ofstream(good) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n";
  struct Case {
    std::string arguments;
    int exit_code;
  };
  const Case cases[] = {{"--scene " + (folder / "missing.obj").string(), 2},
                        {"--scene " + broken, 1},
                        {"--scene " + good + " --scale 10", 2},
                        {"--scene " + good + " --subdivisions 3", 2},
                        {"--json " + (folder / "no" / "such" / "r.json").string(), 1},
                        {"--light-dir 0,0,0", 2},
                        {"--light-dir 1,2", 2},
                        {"--shading glossy", 2},
                        {"--shadows maybe", 2},
                        {"--ambient -1", 2},
                        {"--eye 0,1,0 --target 0,1,0", 2},
                        {"--width 0", 2},
                        {"--output picture.jpg", 2}};
  for (const Case& c : cases) {
    const ProgramRun run = run_program(c.arguments);
    CAPTURE(c.arguments, run.output);
    CHECK(run.exit_code == c.exit_code);
    CHECK_THAT(run.output, rt::testing::starts_with("ch06_lambertian_shading: error: "));
    CHECK(rt::testing::line_count(run.output) == 1);
  }
  // A good file renders, framed automatically.
  const std::string image = (folder / "good.png").string();
  const ProgramRun ok =
      run_program("--scene " + good + " --width 32 --height 18 --image-only --output " + image);
  CAPTURE(ok.output);
  CHECK(ok.exit_code == 0);
  CHECK(std::filesystem::file_size(image) > 0);
  std::filesystem::remove_all(folder);
}

TEST_CASE("program: a run that fails on one output replaces none of the others", "[ch06]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch06_outputs");
  const std::filesystem::path image = folder / "keep.png", report = folder / "keep.json";
  std::ofstream(image) << "the image of an earlier run";
  std::ofstream(report) << "the report of an earlier run";
  const auto contents = [](const std::filesystem::path& path) {
    std::ifstream in(path);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  // The image is written first, then the report fails (/dev/full): the image stays as it was.
  const ProgramRun full = run_program("--width 16 --height 12 --frames 1 --output " +
                                      image.string() + " --json /dev/full");
  CAPTURE(full.output);
  CHECK(full.exit_code == 1);
  CHECK_THAT(full.output, rt::testing::contains("/dev/full"));
  CHECK(contents(image) == "the image of an earlier run");
  // The same run with both paths good replaces both.
  const ProgramRun ok = run_program("--width 16 --height 12 --frames 1 --output " +
                                    image.string() + " --json " + report.string());
  CAPTURE(ok.output);
  CHECK(ok.exit_code == 0);
  CHECK(contents(image).starts_with("\x89PNG"));
  CHECK(contents(report).starts_with("{"));
  // An .exr of the picture, and a report under an image's name refused before the work.
  const ProgramRun exr = run_program("--width 16 --height 12 --image-only --output " +
                                     (folder / "picture.exr").string());
  CAPTURE(exr.output);
  CHECK(exr.exit_code == 0);
  CHECK(std::filesystem::file_size(folder / "picture.exr") > 0);
  const ProgramRun misnamed = run_program("--json " + (folder / "report.png").string());
  CHECK(misnamed.exit_code == 2);
  CHECK(rt::testing::line_count(misnamed.output) == 1);
  std::filesystem::remove_all(folder);
}

TEST_CASE("program: .pfm and .exr hold the shading's linear values, the PNG their picture",
          "[ch06]") {
  const std::filesystem::path folder = rt::testing::temp_folder("rt_ch06_linear");
  const std::string size = "--width 24 --height 16 --image-only --output ";
  for (const char* name : {"frame.png", "frame.pfm", "frame.exr"}) {
    const ProgramRun run = run_program(size + (folder / name).string());
    CAPTURE(run.output);
    REQUIRE(run.exit_code == 0);
  }
  const Image png = rt::testing::read_png(folder / "frame.png");
  const LinearImage pfm = rt::testing::read_pfm(folder / "frame.pfm");
  const LinearImage exr = rt::testing::read_exr(folder / "frame.exr");
  REQUIRE(pfm.rgb.size() == png.pixels.size());
  CHECK(exr.rgb == pfm.rgb);
  // The picture is the linear values through the chapter's curve (square root, clipped), so
  // the files agree pixel for pixel; the 8-bit values themselves (v / 255) would not.
  int lit = 0;
  for (std::size_t i = 0; i < pfm.rgb.size(); ++i) {
    CAPTURE(i, pfm.rgb[i].x, png.pixels[i].r);
    CHECK(ch03::to_rgba8(pfm.rgb[i]) == png.pixels[i]);
    lit += pfm.rgb[i].x > 0.0f ? 1 : 0;
  }
  CHECK(lit > 0);
  std::filesystem::remove_all(folder);
}

TEST_CASE("program: the window's screenshot is a picture, refused as a linear file", "[ch06]") {
  // Refused before a window is asked for, so with a display or without.
  const ProgramRun run = rt::testing::run_command(
      std::string(RT_CH06_PROGRAM) + " --backend cpu --window --frames 2 --output shot.exr");
  CAPTURE(run.output);
  CHECK(run.exit_code == 2);
  CHECK(rt::testing::line_count(run.output) == 1);
  CHECK_THAT(run.output, rt::testing::contains("screenshot, a picture"));
}
