// Chapter 03: the sphere scene on both backends, and its reference. See render.h.
#include "render.h"

#include <cmath>

#include "rt/error.h"
#include "trace.h"

namespace rt::ch03 {

// [listing:render_spheres]
void render_spheres(Backend backend, const SphereScene<float>& scene,
                    const Camera<float>& camera, Extent extent, TraceSettings settings,
                    Rgba8* pixels, PixelRecord* records) {
  const int width = extent.width;
  // The scene and camera are captured by value: they travel as kernel arguments.
  for_each_pixel(backend, extent, [=] RT_HD(int x, int y) {
    const PixelTrace<float> traced = trace_pixel(scene, camera, x, y, settings);
    const int index = y * width + x;
    pixels[index] = to_rgba8(traced.colour);
    if (records != nullptr)
      records[index] = {traced.t, traced.sphere, has_nan(traced.colour) ? 1 : 0, traced.rays};
  });
}
// [/listing:render_spheres]

ReferenceFrame render_reference(const SphereScene<float>& scene, const CameraSpec& spec,
                                Extent extent, int max_depth) {
  const SphereScene<double> scene64 = scene.as<double>();
  const FloatRaysInDouble camera{make_camera<float>(spec, extent)};
  ReferenceFrame reference{Image(extent.width, extent.height),
                           std::vector<double>(extent.pixel_count()),
                           std::vector<int>(extent.pixel_count())};
  std::vector<int> rays(extent.pixel_count());
  for_each_pixel_cpu(extent, [&](int x, int y) {
    const PixelTrace<double> traced =
        trace_pixel(scene64, camera, x, y, TraceSettings{SphereVariant::stable, max_depth});
    const std::size_t index = static_cast<std::size_t>(y) * extent.width + x;
    reference.image.pixels[index] = to_rgba8(traced.colour);
    reference.t[index] = traced.t;
    reference.sphere[index] = traced.sphere;
    rays[index] = traced.rays;
  });
  for (const int pixel_rays : rays) reference.rays += pixel_rays;
  return reference;
}

FrameError compare_with_reference(const Image& image, const std::vector<PixelRecord>& records,
                                  const ReferenceFrame& reference) {
  if (image.pixels.size() != reference.image.pixels.size() ||
      records.size() != reference.t.size())
    throw Error("compare_with_reference: the frame and its reference differ in size");
  FrameError error;
  error.pixels_differing =
      static_cast<long long>(count_differing_pixels(image.pixels, reference.image.pixels));
  for (std::size_t i = 0; i < records.size(); ++i) {
    const PixelRecord& r = records[i];
    error.nan_pixels += r.nan;
    const int expected = reference.sphere[i];
    if (r.sphere >= 0 && r.sphere != expected) ++error.false_hits;
    if (r.sphere < 0 && expected >= 0) ++error.false_misses;
    if (r.sphere >= 0 && r.sphere == expected) {
      const double relative = std::abs(double(r.t) - reference.t[i]) / reference.t[i];
      // A NaN t with the right sphere would be hidden by max(): count it as infinite error.
      error.max_relative_t_error =
          std::isnan(relative) ? INFINITY : std::max(error.max_relative_t_error, relative);
    }
  }
  return error;
}

} // namespace rt::ch03
