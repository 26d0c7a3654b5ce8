// Chapter 01: the first kernel launch. Renders the block pattern with the hand-written kernel,
// with the launch helper on both backends, and with the flat offset check that the first
// version of this program used; then prints what each costs and what each gets wrong.
#include <iostream>
#include <sstream>

#include "first_kernel.h"
#include "launch_report.h"
#include "rt/cli.h"
#include "rt/error.h"
#include "rt/program_output.h"
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

int run(const CommonOptions& options, BlockShape block, const std::string& flat_output) {
  const Backend backend = resolve_backend(options.backend, std::cout);
  const Extent extent = options.extent();
  Report report =
      start_report("Chapter 01: the first kernel launch", "Mpix/s", "CPU reference", backend);
  report.add_context("image", to_string(extent) + ", blocks of " + std::to_string(block.x) +
                                  "x" + std::to_string(block.y) + " threads");

  // The reference: the launch helper on CPU threads.
  Image reference(extent.width, extent.height);
  const Timing cpu = time_on(
      Backend::cpu,
      [&] { render_block_pattern(Backend::cpu, reference.pixels.data(), extent, block); },
      options.frames);
  Image shown = reference;
  bool backends_agree = true;
  if (backend == Backend::gpu) {
    shown = report_gpu_kernels(extent, block, options.frames, reference, report);
    backends_agree =
        report.rows()[0].metrics[0].second == 0 && report.rows()[1].metrics[0].second == 0;
  }
  report.add_row({"launch helper",
                  "cpu",
                  cpu.median_ms,
                  extent.pixel_count() / 1e6 / (cpu.median_ms * 1e-3),
                  "reference",
                  {{"pixels_differing", 0.0}}});

  std::vector<Rgba8> flat_image(reference.pixels.size() + 1);
  const Timing flat_cpu = time_on(
      Backend::cpu, [&] { run_flat_offset_cpu(flat_image, extent, block); }, options.frames);
  report.add_row(
      audit_row("flat offset check (grid replayed)", Backend::cpu, flat_cpu, extent, block));

  if (!options.output.empty()) write_output_image(options.output, shown);
  if (!flat_output.empty())
    write_output_image(flat_output, flat_offset_damage(reference, flat_image));
  finish_report(report, options);
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
  return run_main(app, argc, argv, options, [&] {
    if (!flat_output.empty()) check_image_path(flat_output);
    return run(options, parse_block(block_text), flat_output);
  });
}
