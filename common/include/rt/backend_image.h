// An image rendered on either backend (chapter 01): the render writes into host memory on the
// CPU, or into a device buffer that is then copied back on the GPU. Reference images and test
// images in every chapter come through here, and the linear values of chapters that compute
// radiance.
#pragma once

#include "rt/backend.h"
#include "rt/device_buffer.h"
#include "rt/image.h"
#include "rt/launch.h"

namespace rt {

// `render(pixels)` must fill extent.width * extent.height pixels on the resolved backend.
template <class Render>
Image render_into_image(Backend backend, Extent extent, Render&& render) {
  Image image(extent.width, extent.height);
  if (backend == Backend::cpu) {
    render(image.pixels.data());
    return image;
  }
  DeviceBuffer<Rgba8> d_image(image.pixels.size());
  render(d_image.data());
  d_image.download(image.pixels);
  return image;
}

// `render(pixels, radiance)` must fill both, extent.width * extent.height each, on the resolved
// backend: the picture and each pixel's linear values. The linear values come back.
template <class Render>
LinearImage render_into_linear_image(Backend backend, Extent extent, Render&& render) {
  const std::size_t count = static_cast<std::size_t>(extent.pixel_count());
  LinearImage image{extent.width, extent.height, std::vector<Vec3f>(count)};
  if (backend == Backend::cpu) {
    std::vector<Rgba8> pixels(count);
    render(pixels.data(), image.rgb.data());
    return image;
  }
  DeviceBuffer<Rgba8> d_pixels(count);
  DeviceBuffer<Vec3f> d_radiance(count);
  render(d_pixels.data(), d_radiance.data());
  d_radiance.download(image.rgb);
  return image;
}

} // namespace rt
