// An image rendered on either backend (chapter 01): the render writes into host memory on the
// CPU, or into a device buffer that is then copied back on the GPU. Reference images and test
// images in every chapter come through here.
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

} // namespace rt
