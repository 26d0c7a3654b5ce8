// Chapter 03 tests of the supported range (supported_range.h) at the camera: both sides of
// every bound, cameras that only float makes degenerate, and a field of view too narrow for
// its image. Inside the range every neighbouring pixel gets its own ray.
#include <cmath>
#include <functional>
#include <string>

#include <SDL.h>

#include "rt_catch.h"

#include "camera_cli.h"
#include "camera_spec.h"
#include "orbit_controls.h"
#include "rt/error.h"
#include "supported_range.h"

using namespace rt;
using namespace rt::ch03;
using rt::testing::contains;

namespace {

std::string usage_error(const std::function<void()>& check) {
  try {
    check();
  } catch (const UsageError& e) {
    return e.what();
  }
  return "no error";
}

std::string refusal(const CameraSpec& spec) {
  return usage_error([&] { validate_camera(spec); });
}

std::string spacing_refusal(const CameraSpec& spec, Extent extent) {
  return usage_error([&] { check_pixel_spacing(spec, extent); });
}

CameraSpec looking_at_origin(Vec3d eye) {
  CameraSpec spec;
  spec.eye = eye;
  spec.target = {0.0, 0.0, 0.0};
  return spec;
}

// True when every pixel's ray differs from the next one's, along a row and down a column.
bool neighbours_differ(const CameraSpec& spec, Extent extent) {
  const Camera<float> camera = make_camera<float>(spec, extent);
  const auto same = [](const Ray<float>& a, const Ray<float>& b) {
    return a.origin == b.origin && a.direction == b.direction;
  };
  for (int j = 0; j + 1 < extent.height; ++j)
    if (same(camera.ray_through_pixel(extent.width / 2, j),
             camera.ray_through_pixel(extent.width / 2, j + 1)))
      return false;
  for (int i = 0; i + 1 < extent.width; ++i)
    if (same(camera.ray_through_pixel(i, extent.height / 2),
             camera.ray_through_pixel(i + 1, extent.height / 2)))
      return false;
  return true;
}

} // namespace

TEST_CASE("camera: coordinates up to the supported bound, and not beyond", "[ch03]") {
  CHECK(refusal(looking_at_origin({0.0, 0.0, k_max_coordinate})) == "no error");
  CHECK_THAT(refusal(looking_at_origin({0.0, 0.0, 1.0001 * k_max_coordinate})),
             contains("--eye 0,0,1e+10 is outside the supported range"));
  CHECK_THAT(refusal(looking_at_origin({1e38, 0.0, 0.0})),
             contains("outside the supported range: coordinates lie within +-1e+10"));
  CameraSpec far_target = looking_at_origin({0.0, 0.0, 1.0});
  far_target.target = {0.0, 0.0, -2e10};
  CHECK_THAT(refusal(far_target), contains("--target"));
}

TEST_CASE("camera: eye and target distinct in double but not in float are refused", "[ch03]") {
  CameraSpec spec = looking_at_origin({1.0, 1.0, 1.0});
  spec.target = {1.0 + 1e-10, 1.0, 1.0}; // the same float as the eye
  CHECK_THAT(refusal(spec), contains("the same point in float"));
  // Closer than the shortest supported length, though float tells them apart.
  spec.eye = {0.0, 0.0, 0.9e-10};
  spec.target = {0.0, 0.0, 0.0};
  CHECK_THAT(refusal(spec), contains("apart; the shortest supported distance is 1e-10"));
  spec.eye = {0.0, 0.0, k_min_length};
  CHECK(refusal(spec) == "no error");
  // Up within 0.06 degrees of the view direction: float would choose the roll.
  CameraSpec steep = looking_at_origin({0.0, 0.0, 5.0});
  steep.up = {0.0, 0.5e-3, 1.0};
  CHECK_THAT(refusal(steep), contains("parallel to the view direction"));
  steep.up = {0.0, 2e-3, 1.0};
  CHECK(refusal(steep) == "no error");
}

TEST_CASE("camera: a field of view too narrow for the image is refused, with the narrowest",
          "[ch03]") {
  const Extent extent{64, 720};
  CameraSpec spec = looking_at_origin({0.0, 0.0, 5.0});
  spec.fov_degrees = 0.001;
  CHECK_THAT(spacing_refusal(spec, extent),
             contains("--fov 0.001 is too narrow for an image 720 pixels high") &&
                 contains("the narrowest here is about 0.0393 degrees"));
  CHECK_THROWS_AS(make_camera<float>(spec, extent), UsageError);
  spec.fov_degrees = 0.038;
  CHECK_THROWS_AS(make_camera<float>(spec, extent), UsageError);
  // At the narrowest accepted field of view every pixel still has a ray of its own.
  spec.fov_degrees = 0.0395;
  CHECK(spacing_refusal(spec, extent) == "no error");
  CHECK(neighbours_differ(spec, extent));
  // A smaller image takes a narrower view.
  CHECK(spacing_refusal(spec, {64, 72}) == "no error");
}

TEST_CASE("camera: an orthographic view too small for its distance from the origin", "[ch03]") {
  CameraSpec spec;
  spec.kind = CameraKind::orthographic;
  spec.eye = {1e7, 1e7 + 2.2, 1e7 + 6.5};
  spec.target = {1e7 + 0.3, 1e7 + 0.7, 1e7};
  CHECK_THAT(spacing_refusal(spec, {1280, 720}),
             contains("would start their rays at the same point in float"));
  spec.eye = {0.0, 2.2, 6.5};
  spec.target = {0.3, 0.7, 0.0};
  CHECK(spacing_refusal(spec, {1280, 720}) == "no error");
  CHECK(neighbours_differ(spec, {1280, 720}));
}

TEST_CASE("the window's controls stop at the edge of what the camera can show", "[ch03]") {
  const CameraSpec start;
  OrbitControls controls(start);
  SDL_Event wheel{};
  wheel.type = SDL_MOUSEWHEEL;
  wheel.wheel.y = 1; // one step in: 0.9 of the distance
  for (int step = 0; step < 2000; ++step) controls.handle(wheel);
  CHECK(refusal(controls.camera()) == "no error");
  CHECK(length(controls.camera().eye - controls.camera().target) >= k_min_length);
  wheel.wheel.y = -1;
  for (int step = 0; step < 4000; ++step) controls.handle(wheel);
  CHECK(refusal(controls.camera()) == "no error");
  CHECK(max_component(elementwise_abs(controls.camera().eye)) <= k_max_coordinate);
  CHECK(length(controls.camera().eye - controls.camera().target) > 1e9);
}
