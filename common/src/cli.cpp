// Command-line plumbing (chapter 01): see rt/cli.h.
#include "rt/cli.h"

#include <iostream>
#include <new>

#include "rt/cuda_check.h"
#include "rt/error.h"
#include "rt/image.h"
#include "rt/output_file.h"
#include "rt/report.h"

namespace rt {

CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return "not a number: " + text;
        if (!(value >= lo && value <= hi))
          return "Value " + text + " not a finite number in range " +
                 CLI::detail::to_string(lo) + " to " + CLI::detail::to_string(hi);
        return {};
      },
      "FINITE in [" + CLI::detail::to_string(lo) + " - " + CLI::detail::to_string(hi) + "]");
}

CLI::Option* add_on_off_option(CLI::App& app, const std::string& name, bool& value,
                               const std::string& help) {
  return app
      .add_option_function<std::string>(
          name, [&value](const std::string& text) { value = text == "on"; }, help)
      ->check(CLI::IsMember({"on", "off"}))
      ->default_str(value ? "on" : "off");
}

void add_help_paragraph(CLI::App& app, const std::string& paragraph) {
  const std::string& footer = app.get_footer();
  app.footer(footer.empty() ? paragraph : footer + "\n\n" + paragraph);
}

void add_image_size_options(CLI::App& app, int& width, int& height) {
  const auto side = CLI::Range(1, k_max_image_side);
  app.add_option("--width", width, "Image width in pixels")->check(side)->capture_default_str();
  app.add_option("--height", height, "Image height in pixels")
      ->check(side)
      ->capture_default_str();
  app.final_callback([&width, &height] {
    const long long pixels = Extent{width, height}.pixel_count();
    if (pixels > k_max_image_pixels)
      throw CLI::ValidationError("--width and --height",
                                 std::to_string(width) + "x" + std::to_string(height) + " is " +
                                     std::to_string(pixels) + " pixels, more than the " +
                                     std::to_string(k_max_image_pixels) + " an image may have");
  });
  add_help_paragraph(app, "Images: at most " + std::to_string(k_max_image_side) +
                              " pixels a side and " + std::to_string(k_max_image_pixels) +
                              " in all (8K UHD fits).");
}

void add_common_options(CLI::App& app, CommonOptions& options) {
  add_image_size_options(app, options.width, options.height);
  app.add_option("-o,--output", options.output,
                 "Image file to write: .png (the picture), .pfm or .exr (32-bit floats: the "
                 "linear radiance where the chapter computes it, from chapter 06 on; else the "
                 "picture's values)")
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--backend",
         [&options](const std::string& text) { options.backend = parse_backend(text); },
         "Where to run: auto (GPU if usable, else CPU), gpu or cpu")
      ->check(CLI::IsMember({"auto", "gpu", "cpu"}))
      ->default_str("auto");
  app.add_option("--frames", options.frames,
                 "Timed runs per variant (default: 50 on the GPU, 5 on the CPU)")
      ->check(CLI::Range(1, 100000));
  app.add_option("--json", options.json, "Also write the report as JSON to this file");
  add_help_paragraph(app, "Output files are written whole or not at all, and only when the "
                          "whole run succeeds: a failed run leaves what was at every path.");
}

void warn(const std::string& what) {
  std::cout.flush(); // the warning lands between the lines it belongs between
  std::cerr << "warning: " << what << std::endl;
}

int run_main(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  const std::string program = app.get_name().empty() ? "rt" : app.get_name();
  auto fail = [&](const std::string& message, int code) {
    std::cout.flush();
    std::cerr << program << ": error: " << message << "\n";
    return code;
  };
  try {
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      if (e.get_exit_code() == 0) return app.exit(e); // --help: print it, exit 0
      return fail(e.what(), 2);
    }
    OutputStaging staging; // the run's files replace earlier ones only if it succeeds
    const int code = body();
    staging.commit();
    return code;
  } catch (const UsageError& e) {
    return fail(e.what(), 2);
  } catch (const CudaError& e) {
    return fail(std::string("CUDA: ") + e.what(), 1);
  } catch (const Error& e) {
    return fail(e.what(), 1);
  } catch (const std::bad_alloc&) {
    return fail("out of host memory", 1);
  } catch (const std::exception& e) {
    return fail(std::string("unexpected: ") + e.what(), 1);
  }
}

int run_main(CLI::App& app, int argc, char** argv, const CommonOptions& options,
             const std::function<int()>& body) {
  return run_main(app, argc, argv, [&] {
    if (!options.output.empty()) check_image_path(options.output);
    if (!options.json.empty()) check_report_path(options.json);
    return body();
  });
}

} // namespace rt
