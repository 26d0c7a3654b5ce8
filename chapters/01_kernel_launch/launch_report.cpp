// Chapter 01: the report's rows. See launch_report.h.
#include "launch_report.h"

#include "rt/device_buffer.h"

namespace rt::ch01 {
namespace {

std::string audit_summary(const WriteAudit& a) {
  return group_digits(a.never_written) + " px never written, " +
         group_digits(a.written_repeatedly) + " px written twice or more, " +
         group_digits(a.past_the_end) + " write(s) past the end";
}

std::vector<std::pair<std::string, double>> audit_metrics(const WriteAudit& a) {
  return {{"never_written", double(a.never_written)},
          {"written_repeatedly", double(a.written_repeatedly)},
          {"writes_past_the_end", double(a.past_the_end)}};
}

// A kernel's row: its time, and how many pixels of its image differ from the reference.
ReportRow compare_row(std::string variant, Backend backend, const Timing& timing, Extent extent,
                      const Image& image, const Image& reference) {
  const auto differing = count_differing_pixels(image.pixels, reference.pixels);
  return {std::move(variant),
          to_string(backend),
          timing.median_ms,
          extent.pixel_count() / (timing.median_ms * 1e3),
          group_digits(static_cast<long long>(differing)) + " px differ",
          {{"pixels_differing", double(differing)}}};
}

} // namespace

ReportRow audit_row(std::string variant, Backend backend, const Timing& timing, Extent extent,
                    BlockShape block) {
  const WriteAudit audit =
      audit_writes(count_flat_offset_writes(backend, extent, block), extent);
  return {std::move(variant),   to_string(backend),
          timing.median_ms,     extent.pixel_count() / 1e6 / (timing.median_ms * 1e-3),
          audit_summary(audit), audit_metrics(audit)};
}

Image report_gpu_kernels(Extent extent, BlockShape block, int frames, const Image& reference,
                         Report& report) {
  // The first launch, every CUDA call written out: its image, and its time before any warm-up.
  const FirstFrame first = render_first_frame_by_hand(extent, block);
  report.add_context("first launch", format_fixed(first.kernel_ms, 3) +
                                         " ms (timed by hand, before any warm-up)");
  DeviceBuffer<Rgba8> d_image(reference.pixels.size());
  Image image(extent.width, extent.height);

  const Timing hand = time_on(
      Backend::gpu, [&] { launch_first_kernel(d_image.data(), extent, block); }, frames);
  report.add_row(
      compare_row("hand-written kernel", Backend::gpu, hand, extent, first.image, reference));

  d_image.fill_bytes(0);
  const Timing helper = time_on(
      Backend::gpu, [&] { render_block_pattern(Backend::gpu, d_image.data(), extent, block); },
      frames);
  d_image.download(image.pixels);
  report.add_row(compare_row("launch helper", Backend::gpu, helper, extent, image, reference));

  DeviceBuffer<Rgba8> d_flat(reference.pixels.size() + 1);
  const Timing flat = time_on(
      Backend::gpu, [&] { launch_flat_offset_kernel(d_flat.data(), extent, block); }, frames);
  report.add_row(audit_row("flat offset check", Backend::gpu, flat, extent, block));
  return image;
}

Image flat_offset_damage(const Image& reference, const std::vector<Rgba8>& flat_image) {
  Image damage(reference.width, reference.height);
  for (std::size_t i = 0; i < damage.pixels.size(); ++i) {
    const Rgba8 p = reference.pixels[i];
    damage.pixels[i] = flat_image[i] == p ? Rgba8{std::uint8_t(p.r / 3), std::uint8_t(p.g / 3),
                                                  std::uint8_t(p.b / 3), 255}
                                          : Rgba8{255, 255, 255, 255};
  }
  return damage;
}

} // namespace rt::ch01
