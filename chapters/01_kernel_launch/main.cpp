// Chapter 01: the first kernel launch. Renders the block pattern with the hand-written kernel,
// with the launch helper on both backends, and with the flat offset check that the first
// version of this program used; then prints what each costs and what each gets wrong.
#include <algorithm>
#include <iostream>
#include <sstream>

#include "first_kernel.h"
#include "rt/cli.h"
#include "rt/device_buffer.h"
#include "rt/error.h"
#include "rt/report.h"
#include "rt/timer.h"

namespace {

using namespace rt;
using namespace rt::ch01;

BlockShape parse_block(const std::string& text) {
  int x = 0, y = 0;
  char by = 0;
  std::istringstream in(text);
  if (!(in >> x >> by >> y) || by != 'x' || !in.eof() || x < 1 || y < 1 || x * y > 1024)
    throw UsageError("--block '" + text + "': expected WxH with W*H between 1 and 1024");
  return {x, y};
}

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

int run(const CommonOptions& options, BlockShape block, const std::string& flat_output) {
  const Backend backend = resolve_backend(options.backend, std::cout);
  const Extent extent = options.extent();
  const double mpix = extent.pixel_count() / 1e6;

  Report report("Chapter 01: the first kernel launch", "Mpix/s", "CPU reference");
  report.add_context("device", describe_backend(backend));
  report.add_context("image", std::to_string(extent.width) + "x" +
                                  std::to_string(extent.height) + ", blocks of " +
                                  std::to_string(block.x) + "x" + std::to_string(block.y) +
                                  " threads");

  // The reference: the launch helper on CPU threads.
  Image reference(extent.width, extent.height);
  const Timing cpu = time_on(
      Backend::cpu,
      [&] { render_block_pattern(Backend::cpu, reference.pixels.data(), extent, block); },
      options.frames);
  Image shown = reference;
  bool backends_agree = true;

  if (backend == Backend::gpu) {
    DeviceBuffer<Rgba8> d_image(reference.pixels.size());
    Image image(extent.width, extent.height);

    const Timing hand = time_on(
        Backend::gpu, [&] { launch_first_kernel(d_image.data(), extent, block); },
        options.frames);
    d_image.download(image.pixels);
    report.add_row(compare_row("hand-written kernel", backend, hand, extent, image, reference));

    d_image.fill_bytes(0);
    const Timing helper = time_on(
        Backend::gpu,
        [&] { render_block_pattern(Backend::gpu, d_image.data(), extent, block); },
        options.frames);
    d_image.download(image.pixels);
    report.add_row(compare_row("launch helper", backend, helper, extent, image, reference));
    backends_agree =
        report.rows()[0].metrics[0].second == 0 && report.rows()[1].metrics[0].second == 0;
    shown = image;

    DeviceBuffer<Rgba8> d_flat(reference.pixels.size() + 1);
    const Timing flat = time_on(
        Backend::gpu, [&] { launch_flat_offset_kernel(d_flat.data(), extent, block); },
        options.frames);
    const WriteAudit gpu_audit =
        audit_writes(count_flat_offset_writes(Backend::gpu, extent, block), extent);
    report.add_row({"flat offset check", "gpu", flat.median_ms, mpix / (flat.median_ms * 1e-3),
                    audit_summary(gpu_audit), audit_metrics(gpu_audit)});
  }

  report.add_row({"launch helper",
                  "cpu",
                  cpu.median_ms,
                  mpix / (cpu.median_ms * 1e-3),
                  "reference",
                  {{"pixels_differing", 0.0}}});

  std::vector<Rgba8> flat_image(reference.pixels.size() + 1);
  const Timing flat_cpu = time_on(
      Backend::cpu, [&] { run_flat_offset_cpu(flat_image, extent, block); }, options.frames);
  const WriteAudit cpu_audit =
      audit_writes(count_flat_offset_writes(Backend::cpu, extent, block), extent);
  report.add_row({"flat offset check (grid replayed)", "cpu", flat_cpu.median_ms,
                  mpix / (flat_cpu.median_ms * 1e-3), audit_summary(cpu_audit),
                  audit_metrics(cpu_audit)});

  if (!options.output.empty()) {
    write_image(options.output, shown);
    std::cout << "wrote " << options.output << "\n";
  }
  if (!flat_output.empty()) {
    // Where the flat offset check went wrong: wrong pixels in white, the rest dimmed.
    Image damage(extent.width, extent.height);
    for (std::size_t i = 0; i < damage.pixels.size(); ++i) {
      const Rgba8 p = reference.pixels[i];
      damage.pixels[i] =
          flat_image[i] == p
              ? Rgba8{std::uint8_t(p.r / 3), std::uint8_t(p.g / 3), std::uint8_t(p.b / 3), 255}
              : Rgba8{255, 255, 255, 255};
    }
    write_image(flat_output, damage);
    std::cout << "wrote " << flat_output << "\n";
  }
  report.print(std::cout);
  if (!options.json.empty()) report.write_json(options.json);
  if (!backends_agree) throw Error("the GPU image differs from the CPU reference");
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 01: the first kernel launch, and the launch helper",
               "ch01_kernel_launch"};
  CommonOptions options;
  options.output = "ch01_kernel_launch.png";
  add_common_options(app, options);
  std::string block_text = "16x16";
  app.add_option("--block", block_text, "Threads per block, WxH")->capture_default_str();
  std::string flat_output;
  app.add_option("--flat-output", flat_output,
                 "Also write where the flat offset check draws wrong pixels (white)");
  return run_main(app, argc, argv, [&] {
    if (!options.output.empty()) check_image_path(options.output);
    if (!flat_output.empty()) check_image_path(flat_output);
    return run(options, parse_block(block_text), flat_output);
  });
}
