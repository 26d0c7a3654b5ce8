// Chapter 05 tests of what the loader refuses beyond the supported range (chapter 03's
// supported_range.h), on both sides of each bound: coordinates, the span of a triangle with
// area, a mesh of flat triangles only, an empty file name; the automatic camera that cannot
// frame a model names why; and a tiny and a huge model inside the range render as the float64
// reference does, with no NaN and no holes.
#include <cstdio>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "camera_spec.h"
#include "model_render.h"
#include "obj_loader.h"
#include "rt/error.h"
#include "supported_range.h"

using namespace rt;
using namespace rt::ch05;
using rt::testing::contains;

namespace {

std::string input_error(const std::function<void()>& load) {
  try {
    load();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

std::string parse_error(const std::string& text) {
  return input_error([&] { parse_obj(text, "model.obj"); });
}

// One triangle with corners at the origin, at size on x and at size on y.
std::string triangle_text(const std::string& size) {
  return "v 0 0 0\nv " + size + " 0 0\nv 0 " + size + " 0\nf 1 2 3\n";
}

// An icosphere of radius `scale` written as OBJ text, numbers printed exactly enough.
std::string sphere_text(double scale) {
  const ch04::Mesh sphere = ch04::make_icosphere(2, {0.0, 0.0, 0.0}, scale);
  std::string text;
  char line[128];
  for (const Vec3f& v : sphere.vertices) {
    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", double(v.x), double(v.y),
                  double(v.z));
    text += line;
  }
  for (const ch04::IndexedTriangle& t : sphere.triangles) {
    std::snprintf(line, sizeof line, "f %d %d %d\n", t.v0 + 1, t.v1 + 1, t.v2 + 1);
    text += line;
  }
  return text;
}

} // namespace

TEST_CASE("loader: coordinates up to 1e10 load, beyond are refused at their line", "[ch05]") {
  CHECK(parse_obj(triangle_text("1e10"), "model.obj").geometry.vertices[1].x == 1e10f);
  CHECK(parse_obj(triangle_text("-1e10"), "model.obj").geometry.vertices[1].x == -1e10f);
  CHECK_THAT(parse_error(triangle_text("10000000001")),
             contains("model.obj:2: coordinate '10000000001' is outside the supported range: "
                      "coordinates lie within +-1e+10"));
  CHECK_THAT(parse_error("v 0 0 -3e38\n" + triangle_text("1")),
             contains("model.obj:1: coordinate '-3e38' is outside the supported range"));
  // A fourth number (w) or a vertex colour is not a coordinate.
  CHECK(parse_obj("v 0 0 0 1e20\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "model.obj")
            .geometry.triangles.size() == 1);
}

TEST_CASE("loader: a triangle with area spans at least 1e-10", "[ch05]") {
  CHECK(parse_error(triangle_text("1e-10")) == "no error");
  CHECK_THAT(parse_error(triangle_text("9e-11")),
             contains("model.obj: triangle 0 spans only 9e-11; a triangle with area must span "
                      "at least 1e-10"));
  CHECK_THAT(parse_error(triangle_text("1e-12")), contains("spans only 1e-12"));
  // Corners so close that the triangle is flat in float: valid, counted, never hit.
  const ObjMesh mesh = parse_obj(
      triangle_text("1") + "v 0 0 0\nv 1e-30 0 0\nv 0 1e-30 0\n" + "f 4 5 6\n", "model.obj");
  CHECK(mesh.degenerate_triangle_count == 1);
}

TEST_CASE("loader: a mesh of flat triangles only is refused like a mesh without faces",
          "[ch05]") {
  CHECK_THAT(parse_error("v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\nf 1 1 2\n"),
             contains("model.obj: all 2 triangles are flat (zero area in float): nothing to "
                      "intersect"));
  CHECK_THAT(parse_error("v 0 0 0\n"), contains("model.obj: no faces"));
  CHECK(input_error([] { load_obj(""); }) == "the OBJ file name is empty");
}

TEST_CASE("the automatic camera names why it cannot frame a model", "[ch05]") {
  const CameraSpec spec;
  // Inside the range, but the eye that frames the whole box stands further out.
  CHECK_THAT(input_error([&] {
               frame_bounds({-1e10f, -1e10f, -1e10f}, {1e10f, 1e10f, 1e10f}, spec, {160, 90});
             }),
             contains("cannot frame the model") && contains("beyond the supported +-1e+10") &&
                 contains("give --eye and --target"));
  const CameraSpec framed =
      frame_bounds({-1e9f, -1e9f, -1e9f}, {1e9f, 1e9f, 1e9f}, spec, {160, 90});
  CHECK(max_component(elementwise_abs(framed.eye)) <= ch03::k_max_coordinate);
}

TEST_CASE("a tiny and a huge model inside the range render as the float64 reference does",
          "[ch05]") {
  const Extent extent{80, 60};
  for (const double scale : {1e-9, 1e9}) {
    CAPTURE(scale);
    ObjMesh mesh = parse_obj(sphere_text(scale), "sphere.obj");
    const CameraSpec spec = frame_bounds(mesh.bounds_min, mesh.bounds_max, {}, extent);
    const ch04::TriangleScene scene = take_scene(mesh);
    const PixelSample whole{extent, 1};
    const ch04::MeshReference reference = render_model_reference(scene, spec, whole);
    long long surface = 0;
    for (const int t : reference.triangle) surface += t >= 0;
    CHECK(surface > extent.pixel_count() / 10);
    for (const TriangleVariant variant :
         {TriangleVariant::watertight, TriangleVariant::moller_trumbore}) {
      Image image(extent.width, extent.height);
      std::vector<ch04::MeshPixelRecord> records(extent.pixel_count());
      render_model(Backend::cpu, variant, ch04::host_view(scene.mesh), scene.object.data(),
                   ch03::make_camera<float>(spec, extent), whole, image.pixels.data(),
                   records.data());
      const ch04::MeshFrameError e = ch04::compare_with_reference(image, records, reference);
      CAPTURE(ch04::to_string(variant), e.pixels_differing, e.holes);
      CHECK(e.nan_pixels == 0);
      if (variant == TriangleVariant::watertight) CHECK(e.holes == 0);
      CHECK(e.pixels_differing <= extent.pixel_count() / 100);
    }
  }
}

TEST_CASE("the help sentence names the loader's limits and range", "[ch05]") {
  LoadLimits limits;
  limits.max_triangles = 123;
  const std::string text = describe_load_limits(limits);
  CHECK_THAT(text, contains("at most 123 triangles") && contains("+-1e+10") &&
                       contains("at least 1e-10"));
  CHECK_THAT(describe_load_limits(), contains("at most 10000000 triangles"));
}
