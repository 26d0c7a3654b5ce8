// Chapter 06 tests of the supported range for the built-in scene (--scale) and the automatic
// camera: both sides of each bound, and the shaded scene at the smallest and largest scales
// the range holds against the float64 reference: close, with no NaN.
#include <functional>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "rt/error.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "supported_range.h"

using namespace rt;
using namespace rt::ch06;
using rt::testing::contains;

namespace {

std::string input_error(const std::function<void()>& make) {
  try {
    make();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

} // namespace

TEST_CASE("the built-in scene scales within the supported range, and not beyond", "[ch06]") {
  // The floor reaches 6 scale from the origin; the icosphere's smallest edge is about 0.3
  // scale with two subdivisions.
  CHECK(input_error([] { make_default_scene(2, 1.6e9, LightSettings{}); }) == "no error");
  CHECK_THAT(input_error([] { make_default_scene(2, 1.7e9, LightSettings{}); }),
             contains("the built-in scene scaled by ") && contains("beyond the supported"));
  CHECK(input_error([] { make_default_scene(2, 1e-9, LightSettings{}); }) == "no error");
  CHECK_THAT(input_error([] { make_default_scene(2, 1e-10, LightSettings{}); }),
             contains("spans only"));
  // The command line's --scale range lies inside it, at every subdivision level it allows.
  for (const double scale : {1e-6, 1e7})
    CHECK(input_error([&] { make_default_scene(6, scale, LightSettings{}); }) == "no error");
}

TEST_CASE("the automatic framing names why it cannot frame a scene", "[ch06]") {
  const Bounds edge{{-1e10, -1e10, -1e10}, {1e10, 1e10, 1e10}};
  CHECK_THAT(input_error([&] {
               frame_bounds_down_z(edge, 45.0, {1920, 1080});
             }),
             contains("cannot frame the model") && contains("beyond the supported +-1e+10"));
  const Bounds inside{{-1e9, -1e9, -1e9}, {1e9, 1e9, 1e9}};
  CHECK(max_component(elementwise_abs(frame_bounds_down_z(inside, 45.0, {1920, 1080}).eye)) <=
        ch03::k_max_coordinate);
}

TEST_CASE("the shaded scene at the smallest and largest scales matches the float64 reference",
          "[ch06]") {
  const Extent extent{80, 45};
  for (const double scale : {1e-9, 1e9}) {
    const ShadedScene scene = make_default_scene(1, scale, LightSettings{});
    const CameraSpec spec = default_camera(scale);
    for (const bool smooth : {false, true}) {
      const unsigned features = features_used(scene, smooth, true);
      Image image(extent.width, extent.height);
      std::vector<ShadedPixelRecord> records(extent.pixel_count());
      render_shaded(Backend::cpu, KernelKind::specialised, features, host_view(scene, features),
                    ch03::make_camera<float>(spec, extent), extent, image.pixels.data(),
                    records.data());
      const ShadedReference reference = render_shaded_reference(scene, features, spec, extent);
      const ShadedFrameError e = compare_with_reference(image, records, reference.image);
      CAPTURE(scale, smooth, e.pixels_differing, e.rmse, e.shadowed_facing);
      CHECK(e.nan_pixels == 0);
      CHECK(e.pixels_differing <= extent.pixel_count() / 100);
      CHECK(e.rmse < 1.0);
    }
  }
}
