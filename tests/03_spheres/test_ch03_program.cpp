// Chapter 03 tests of the program's pieces: the camera flags and their validation, both
// cameras built from one setting, the window's camera controls, and the rendered scene against
// its float64 reference (the stable test must be right where the textbook one is not).
#include <cmath>
#include <vector>

#include <SDL.h>

#include "rt_catch.h"

#include "camera_cli.h"
#include "orbit_controls.h"
#include "render.h"
#include "rt/error.h"
#include "trace.h"

using namespace rt;
using namespace rt::ch03;

namespace {

CameraSpec parse(std::vector<std::string> args) {
  CLI::App app;
  CameraSpec spec;
  add_camera_options(app, spec);
  std::vector<const char*> argv{"test"};
  for (const std::string& a : args) argv.push_back(a.c_str());
  app.parse(static_cast<int>(argv.size()), argv.data());
  return spec;
}

SDL_Event mouse_button(bool down, Uint8 button) {
  SDL_Event e{};
  e.type = down ? SDL_MOUSEBUTTONDOWN : SDL_MOUSEBUTTONUP;
  e.button.button = button;
  return e;
}

SDL_Event mouse_motion(int dx, int dy) {
  SDL_Event e{};
  e.type = SDL_MOUSEMOTION;
  e.motion.xrel = dx;
  e.motion.yrel = dy;
  return e;
}

struct Rendered {
  Image image;
  std::vector<PixelRecord> records;
};

Rendered render_cpu(SphereVariant variant, const CameraSpec& spec, Extent extent) {
  Rendered out{Image(extent.width, extent.height),
               std::vector<PixelRecord>(extent.pixel_count())};
  render_spheres(Backend::cpu, make_default_scene(), make_camera<float>(spec, extent), extent,
                 {variant, 4}, out.image.pixels.data(), out.records.data());
  return out;
}

} // namespace

TEST_CASE("camera flags: x,y,z vectors and the field of view are parsed", "[ch03]") {
  const CameraSpec spec = parse({"--eye", "1,2,3", "--target", "-1,0.5,2", "--up", "0,0,1",
                                 "--fov", "55", "--camera", "orthographic"});
  CHECK(spec.eye == Vec3d{1, 2, 3});
  CHECK(spec.target == Vec3d{-1, 0.5, 2});
  CHECK(spec.up == Vec3d{0, 0, 1});
  CHECK(spec.fov_degrees == 55.0);
  CHECK(spec.kind == CameraKind::orthographic);
  CHECK_THROWS(parse({"--eye", "1,2"}));
  CHECK_THROWS(parse({"--eye", "1,x,3"}));
  CHECK_THROWS(parse({"--camera", "fisheye"}));
}

TEST_CASE("camera validation names what is wrong", "[ch03]") {
  CameraSpec spec;
  CHECK_NOTHROW(validate_camera(spec));
  auto message = [](CameraSpec s) {
    try {
      validate_camera(s);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CameraSpec same = spec;
  same.target = same.eye;
  CHECK_THAT(message(same), rt::testing::contains("same point"));
  CameraSpec parallel = spec;
  parallel.up = spec.target - spec.eye;
  CHECK_THAT(message(parallel), rt::testing::contains("parallel"));
  CameraSpec zero_up = spec;
  zero_up.up = {};
  CHECK_THAT(message(zero_up), rt::testing::contains("zero vector"));
  for (double fov : {0.0, -5.0, 180.0, double(NAN)}) {
    CameraSpec bad = spec;
    bad.fov_degrees = fov;
    CHECK_THAT(message(bad), rt::testing::contains("--fov"));
  }
  CameraSpec infinite = spec;
  infinite.eye.x = INFINITY;
  CHECK_THAT(message(infinite), rt::testing::contains("finite"));
}

TEST_CASE("orthographic camera frames the target plane like the pinhole one", "[ch03]") {
  CameraSpec spec;
  const Extent extent{101, 61}; // odd: a pixel sits on the centre
  spec.kind = CameraKind::orthographic;
  const Camera<float> ortho = make_camera<float>(spec, extent);
  spec.kind = CameraKind::pinhole;
  const Camera<float> pinhole = make_camera<float>(spec, extent);
  // The top edge of the image: both cameras' rays reach the target plane at the same height.
  const RayD o = ray_as<double>(ortho.ray_through_pixel(50, 0));
  const RayD p = ray_as<double>(pinhole.ray_through_pixel(50, 0));
  const Vec3d forward = normalize(spec.target - spec.eye);
  const double distance = length(spec.target - spec.eye);
  const Vec3d on_plane_o = o.origin + o.direction * (dot(spec.target - o.origin, forward) /
                                                     dot(o.direction, forward));
  const Vec3d on_plane_p = p.origin + p.direction * (distance / dot(p.direction, forward));
  CHECK(length(on_plane_o - on_plane_p) < 1e-5 * distance);
}

TEST_CASE("orbit keeps the distance to the target, pan moves eye and target together",
          "[ch03]") {
  const CameraSpec start;
  OrbitControls controls(start);
  const double distance = length(start.eye - start.target);
  controls.handle(mouse_button(true, SDL_BUTTON_LEFT));
  controls.handle(mouse_motion(120, -40));
  controls.handle(mouse_button(false, SDL_BUTTON_LEFT));
  CHECK(controls.camera().target == start.target);
  CHECK(length(controls.camera().eye - start.target) == Approx(distance).epsilon(1e-12));
  CHECK(length(controls.camera().eye - start.eye) > 0.1);
  // Orbiting far upwards stops short of the pole: the camera stays valid.
  controls.handle(mouse_button(true, SDL_BUTTON_LEFT));
  controls.handle(mouse_motion(0, 100000));
  controls.handle(mouse_button(false, SDL_BUTTON_LEFT));
  CHECK_NOTHROW(validate_camera(controls.camera()));

  OrbitControls panning(start);
  panning.handle(mouse_button(true, SDL_BUTTON_RIGHT));
  panning.handle(mouse_motion(30, 10));
  const Vec3d eye_shift = panning.camera().eye - start.eye;
  const Vec3d target_shift = panning.camera().target - start.target;
  CHECK(length(eye_shift) > 0.0);
  CHECK(length(eye_shift - target_shift) < 1e-12);

  SDL_Event wheel{};
  wheel.type = SDL_MOUSEWHEEL;
  wheel.wheel.y = 2;
  OrbitControls zooming(start);
  zooming.handle(wheel);
  CHECK(length(zooming.camera().eye - start.target) == Approx(distance * 0.81));
  SDL_Event reset{};
  reset.type = SDL_KEYDOWN;
  reset.key.keysym.sym = SDLK_r;
  zooming.handle(reset);
  CHECK(zooming.camera().eye == start.eye);
}

TEST_CASE("default scene: the stable render matches float64, the textbook one does not",
          "[ch03]") {
  const Extent extent{480, 270};
  const CameraSpec spec;
  const ReferenceFrame reference = render_reference(make_default_scene(), spec, extent, 4);
  const Rendered stable = render_cpu(SphereVariant::stable, spec, extent);
  const Rendered textbook = render_cpu(SphereVariant::textbook, spec, extent);
  const FrameError s = compare_with_reference(stable.image, stable.records, reference);
  const FrameError t = compare_with_reference(textbook.image, textbook.records, reference);
  CAPTURE(s.pixels_differing, s.max_relative_t_error, t.pixels_differing,
          t.max_relative_t_error);
  CHECK(s.nan_pixels == 0);
  CHECK(s.false_hits == 0);
  CHECK(s.false_misses == 0);
  CHECK(s.max_relative_t_error < 1e-4);
  CHECK(s.pixels_differing < extent.pixel_count() / 200); // rounding at quantisation edges
  // The ground sphere's textbook c = |o - c|^2 - r^2 loses about three digits.
  CHECK(t.max_relative_t_error > 10 * s.max_relative_t_error);
  CHECK(t.pixels_differing > s.pixels_differing);
}

TEST_CASE("the sphere scene's moons are hit by the stable test where float64 hits them",
          "[ch03]") {
  // A camera aimed at the 1:1000 moon, zoomed in so that it covers many pixels.
  CameraSpec spec;
  spec.target = {400.0, 1200.0, -1e4};
  spec.fov_degrees = 0.3;
  const Extent extent{64, 64};
  const ReferenceFrame reference = render_reference(make_default_scene(), spec, extent, 0);
  long long moon_pixels = 0;
  for (int sphere : reference.sphere) moon_pixels += sphere == 5;
  REQUIRE(moon_pixels > 100);
  const Rendered stable = render_cpu(SphereVariant::stable, spec, extent);
  const FrameError s = compare_with_reference(stable.image, stable.records, reference);
  CHECK(s.false_hits + s.false_misses <= 4); // a few silhouette pixels at most
}

TEST_CASE("the mirror depth bounds the rays: depth 0 shows no reflections", "[ch03]") {
  const Extent extent{160, 90};
  const CameraSpec spec;
  Image flat(extent.width, extent.height), mirrored(extent.width, extent.height);
  const SphereScene<float> scene = make_default_scene();
  const Camera<float> camera = make_camera<float>(spec, extent);
  render_spheres(Backend::cpu, scene, camera, extent, {SphereVariant::stable, 0},
                 flat.pixels.data());
  render_spheres(Backend::cpu, scene, camera, extent, {SphereVariant::stable, 4},
                 mirrored.pixels.data());
  // Without bounces the mirror sphere shows only its own facing ratio; with them, the
  // checkerboard and the sky appear in it (and faintly in the coloured spheres).
  CHECK(static_cast<long long>(count_differing_pixels(flat.pixels, mirrored.pixels)) >
        extent.pixel_count() / 50);
}

TEST_CASE("the rays a pixel traces: one in the sky, more where mirrors bounce it", "[ch03]") {
  const Extent extent{160, 90};
  const CameraSpec spec;
  const SphereScene<float> scene = make_default_scene();
  const Camera<float> camera = make_camera<float>(spec, extent);
  std::vector<PixelRecord> records(extent.pixel_count());
  Image image(extent.width, extent.height);
  render_spheres(Backend::cpu, scene, camera, extent, {SphereVariant::stable, 4},
                 image.pixels.data(), records.data());
  CHECK(records[0].sphere == -1); // the top left corner sees the sky
  CHECK(records[0].rays == 1);
  int most = 0;
  for (const PixelRecord& r : records) {
    REQUIRE(r.rays >= 1);
    REQUIRE(r.rays <= 5); // the primary ray and at most 4 bounces
    most = std::max(most, r.rays);
  }
  CHECK(most >= 3); // the mirror sphere reflects the coloured ones, which reflect again
  const ReferenceFrame reference = render_reference(scene, spec, extent, 4);
  CHECK(reference.rays > extent.pixel_count());
}

TEST_CASE("scaled by 2^20 the scene renders the same image, and a fixed 1e-4 offset then "
          "speckles the mirror",
          "[ch03]") {
  const Extent extent{160, 90};
  const CameraSpec spec;
  CameraSpec far = spec;
  const double factor = 1048576.0; // a power of two: every coordinate scales exactly
  far.eye = spec.eye * factor;
  far.target = spec.target * factor;
  const SphereScene<float> scene = make_default_scene();
  const SphereScene<float> big = scene.scaled(float(factor));
  Image at_one(extent.width, extent.height), scaled_offset(extent.width, extent.height),
      fixed_offset(extent.width, extent.height);
  render_spheres(Backend::cpu, scene, make_camera<float>(spec, extent), extent,
                 {SphereVariant::stable, 4}, at_one.pixels.data());
  render_spheres(Backend::cpu, big, make_camera<float>(far, extent), extent,
                 {SphereVariant::stable, 4}, scaled_offset.pixels.data());
  render_spheres(Backend::cpu, big, make_camera<float>(far, extent), extent,
                 {SphereVariant::stable, 4, 1e-4f}, fixed_offset.pixels.data());
  CHECK(count_differing_pixels(at_one.pixels, scaled_offset.pixels) == 0);
  // p + 1e-4 n rounds back to p (an ulp of 1e6 is 0.06): mirror rays re-hit their sphere.
  CHECK(static_cast<long long>(count_differing_pixels(at_one.pixels, fixed_offset.pixels)) >
        extent.pixel_count() / 100);
}
