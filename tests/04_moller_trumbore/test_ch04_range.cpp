// Chapter 04 tests of the supported range for triangles: both sides of every bound of
// check_supported_range and of the moved demo scene, normals of any size, and a tiny and a
// huge scene inside the range rendered against the float64 reference: no NaN, no holes.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "mesh_gen.h"
#include "mesh_render.h"
#include "rt/error.h"
#include "supported_range.h"

using namespace rt;
using namespace rt::ch04;
using rt::ch03::k_max_coordinate;
using rt::ch03::k_min_length;
using rt::testing::contains;

namespace {

std::string input_error(const std::function<void()>& check) {
  try {
    check();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

Mesh one_triangle(Vec3d a, Vec3d b, Vec3d c) {
  Mesh mesh;
  mesh.vertices = {a.as<float>(), b.as<float>(), c.as<float>()};
  mesh.triangles = {{0, 1, 2}};
  return mesh;
}

std::string range_error(const Mesh& mesh) {
  return input_error([&] { check_supported_range(mesh, "the mesh"); });
}

// The demo scene's shapes scaled about the origin: an icosphere and a box.
TriangleScene scaled_scene(double scale) {
  TriangleScene scene;
  const Mesh sphere = make_icosphere(2, Vec3d{-1.2, 1.0, 0.0} * scale, scale);
  const Mesh box = make_box(Vec3d{0.6, 0.0, -0.8} * scale, Vec3d{2.2, 1.6, 0.8} * scale, 2);
  append_mesh(scene.mesh, sphere);
  scene.object.assign(sphere.triangles.size(), 0);
  append_mesh(scene.mesh, box);
  scene.object.resize(scene.mesh.triangles.size(), 1);
  return scene;
}

} // namespace

TEST_CASE("the supported range: coordinates up to 1e10, and not beyond", "[ch04]") {
  const double m = k_max_coordinate;
  CHECK(range_error(one_triangle({m, 0, 0}, {m, 1e3, 0}, {m, 0, 1e3})) == "no error");
  CHECK(range_error(one_triangle({-m, -m, -m}, {m, -m, -m}, {-m, m, m})) == "no error");
  CHECK_THAT(range_error(one_triangle({0, 0, 0}, {1.01 * m, 0, 0}, {0, 1, 0})),
             contains("the mesh: triangle 0 has a vertex at 1.01e+10 from the origin, beyond "
                      "the supported +-1e+10"));
  CHECK_THAT(range_error(one_triangle({0, 0, 0}, {1, 0, 0}, {0, -1e38, 0})),
             contains("beyond the supported"));
}

TEST_CASE("the supported range: triangles with area span at least 1e-10", "[ch04]") {
  const double s = k_min_length;
  CHECK(range_error(one_triangle({0, 0, 0}, {s, 0, 0}, {0, s, 0})) == "no error");
  CHECK_THAT(range_error(one_triangle({0, 0, 0}, {0.9 * s, 0, 0}, {0, 0.9 * s, 0})),
             contains("triangle 0 spans only 9e-11; a triangle that is not flat must span at "
                      "least 1e-10"));
  CHECK_THAT(range_error(one_triangle({0, 0, 0}, {1e-20, 0, 0}, {0, 1e-20, 0})),
             contains("spans only 1e-20"));
  // A flat triangle of any size is fine (never hit) as long as one triangle is not flat.
  Mesh with_flat = one_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  append_mesh(with_flat, one_triangle({0, 0, 0}, {1e-30, 0, 0}, {2e-30, 0, 0}));
  CHECK(is_flat(with_flat.triangle(1)));
  CHECK(range_error(with_flat) == "no error");
  // A mesh of flat triangles only is refused, like a mesh of none.
  CHECK_THAT(range_error(one_triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2})),
             contains("all 1 triangles are flat (zero area in float): nothing to intersect"));
  CHECK_THAT(range_error(Mesh{}), contains("no triangles"));
}

TEST_CASE("the demo scene moves up to the supported bound, and not beyond", "[ch04]") {
  // The floor reaches 6 past the offset: 1e10 - 10 keeps every vertex inside. So far out float
  // keeps z to 1024, and the scene flattens along z; most of its triangles keep their area.
  CHECK_NOTHROW(make_demo_scene(0, {0.0, 0.0, k_max_coordinate - 10.0}));
  CHECK_THAT(input_error([] {
               make_demo_scene(0, {0.0, 0.0, 1.1e10});
             }),
             contains("the scene moved by (0, 0, 1.1e+10): triangle 0 has a vertex at "));
  // Moved along all three axes that far, every triangle is flat in float: nothing to draw.
  const double inside = k_max_coordinate - 10.0;
  CHECK_THAT(input_error([&] {
               make_demo_scene(0, {inside, inside, inside});
             }),
             contains("triangles are flat"));
}

TEST_CASE("unit_normal is normalize wherever that is finite, and finite everywhere", "[ch04]") {
  for (const Vec3f n : {Vec3f{1, 2, 3}, Vec3f{-0.3f, 1e-3f, 7}, Vec3f{0, 0, -2}}) {
    CHECK(unit_normal(n) == normalize(n));
    CHECK(unit_normal(n.as<double>()) == normalize(n.as<double>()));
  }
  // The cross products of the edges of triangles of 1e-12 and of 1e12: normalize() fails for
  // both (its squared length under- or overflows: NaN or 0), unit_normal gives the direction.
  for (const float size : {1e-12f, 1e12f}) {
    const Vec3f n = cross(Vec3f{size, 0, 0}, Vec3f{0, size, size});
    const Vec3f unit = unit_normal(n);
    CAPTURE(size);
    CHECK_FALSE(std::abs(length(normalize(n)) - 1.0f) < 1e-3f);
    CHECK(unit.x == 0.0f);
    CHECK(unit.y == Approx(-std::sqrt(0.5)).epsilon(1e-6));
    CHECK(unit.z == Approx(std::sqrt(0.5)).epsilon(1e-6));
  }
}

TEST_CASE("a tiny and a huge scene inside the range render as the float64 reference does",
          "[ch04]") {
  const Extent extent{96, 64};
  for (const double scale : {2e-9, 1e9}) {
    const TriangleScene scene = scaled_scene(scale);
    CAPTURE(scale);
    REQUIRE(range_error(scene.mesh) == "no error");
    ch03::CameraSpec spec;
    spec.eye = Vec3d{0.0, 2.2, 6.5} * scale;
    spec.target = Vec3d{0.3, 0.7, 0.0} * scale;
    const MeshReference reference = render_triangles_reference(scene, spec, extent);
    long long surface = 0;
    for (const int t : reference.triangle) surface += t >= 0;
    CHECK(surface > extent.pixel_count() / 10); // the reference sees the scene
    for (const TriangleVariant variant :
         {TriangleVariant::watertight, TriangleVariant::moller_trumbore}) {
      Image image(extent.width, extent.height);
      std::vector<MeshPixelRecord> records(image.pixels.size());
      render_triangles(Backend::cpu, variant, host_view(scene.mesh), scene.object.data(),
                       ch03::make_camera<float>(spec, extent), extent, image.pixels.data(),
                       records.data());
      const MeshFrameError e = compare_with_reference(image, records, reference);
      CAPTURE(to_string(variant), e.pixels_differing, e.holes);
      CHECK(e.nan_pixels == 0);
      if (variant == TriangleVariant::watertight) CHECK(e.holes == 0);
      CHECK(e.pixels_differing <= extent.pixel_count() / 100);
    }
  }
}
