// Chapter 06: one pixel of a shaded frame, for any scene type the shading accepts (this
// chapter's brute-force SceneView, or a later chapter's own): the camera ray, its shaded colour
// and the record of what it found.
#pragma once

#include <cstdint>

#include "camera_spec.h"
#include "rt/image.h"
#include "rt/launch.h"
#include "shade.h"

namespace rt::ch06 {

// What the primary ray and its shadow rays found in a pixel: 8 bytes.
struct ShadedPixelRecord {
  std::int32_t triangle;        // the primary hit, -1 for none
  std::uint8_t shadow_rays;     // traced (one per light at most)
  std::uint8_t shadowed_facing; // blocked although the face itself faces the light
  std::uint8_t nan;             // 1 if the colour came out NaN
};
static_assert(sizeof(ShadedPixelRecord) == 8);

// Everything a frame needs besides the features: a kernel argument.
template <class S> struct FrameLaunchOf {
  S scene;
  ch03::Camera<float> camera;
  Extent extent;
  Rgba8* pixels;
  ShadedPixelRecord* records; // may be null
  Vec3f* radiance = nullptr;  // may be null: each pixel's colour before the picture's curve
};

template <class F, class S>
RT_HD void shade_pixel(const FrameLaunchOf<S>& frame, F features, int x, int y) {
  const ShadedSample<float> sample =
      shade_ray(frame.scene, frame.camera.ray_through_pixel(x, y), features);
  const int index = y * frame.extent.width + x;
  frame.pixels[index] = ch03::to_rgba8(sample.colour);
  if (frame.radiance != nullptr) frame.radiance[index] = sample.colour;
  if (frame.records != nullptr)
    frame.records[index] = {sample.triangle, static_cast<std::uint8_t>(sample.shadow_rays),
                            static_cast<std::uint8_t>(sample.shadowed_facing),
                            static_cast<std::uint8_t>(ch03::has_nan(sample.colour) ? 1 : 0)};
}

} // namespace rt::ch06
