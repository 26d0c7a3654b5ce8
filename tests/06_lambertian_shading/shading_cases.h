// Chapter 06 test helpers shared by the CPU and GPU tests and by chapter 08's: a frame and its
// pixel records rendered on the CPU, and how many pixel records two frames disagree on.
#pragma once

#include <span>
#include <vector>

#include "rt/image.h"
#include "shaded_render.h"
#include "shaded_scene.h"

namespace rt::testing {

struct ShadedFrame {
  Image image;
  std::vector<ch06::ShadedPixelRecord> records;
};

// The CPU frame of the kernel `kind` for `features`, given only the arrays that kernel reads.
inline ShadedFrame render_cpu(const ch06::ShadedScene& scene, ch06::KernelKind kind,
                              unsigned features, const ch06::CameraSpec& spec, Extent extent) {
  ShadedFrame frame{Image(extent.width, extent.height),
                    std::vector<ch06::ShadedPixelRecord>(extent.pixel_count())};
  ch06::render_shaded(Backend::cpu, kind, features,
                      ch06::host_view(scene, ch06::uploaded_features(kind, features)),
                      ch03::make_camera<float>(spec, extent), extent, frame.image.pixels.data(),
                      frame.records.data());
  return frame;
}

// Pixels whose records differ: another triangle, another count of shadow rays or of blocked
// ones, or NaN in one frame only.
inline long long records_differing(std::span<const ch06::ShadedPixelRecord> a,
                                   std::span<const ch06::ShadedPixelRecord> b) {
  long long differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const ch06::ShadedPixelRecord &p = a[i], &q = b[i];
    differing += p.triangle != q.triangle || p.shadow_rays != q.shadow_rays ||
                 p.shadowed_facing != q.shadowed_facing || p.nan != q.nan;
  }
  return differing;
}

} // namespace rt::testing
