// Command-line plumbing shared by every chapter (chapter 01): the common options, their
// validation, and run_main(), which turns every error into one clear line and an exit code.
#pragma once

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "rt/backend.h"
#include "rt/launch.h"

namespace rt {

inline constexpr int k_max_image_side = 16384; // larger images are refused as absurd
// The most pixels of one image: 2^25, 8K UHD (7680 x 4320) and a little more. What a small
// machine (2 cores, a few GB) can promise: the image, each pixel's hit and the chapters'
// per-pixel records take about 1.5 GB there, and the CPU backend traces it in minutes, with
// progress lines.
inline constexpr long long k_max_image_pixels = 1LL << 25;

struct CommonOptions {
  int width = 1920;   // image width in pixels
  int height = 1080;  // image height in pixels
  std::string output; // image file to write (.png or .pfm); empty: none
  Backend backend = Backend::automatic;
  int frames = 0;   // timed runs per variant; 0: the protocol's default
  std::string json; // also write the report as JSON here; empty: don't

  Extent extent() const { return {width, height}; }
};

// A check for a floating-point option: a finite number in [lo, hi]. (CLI::Range alone lets
// NaN through, since every comparison with NaN is false.)
CLI::Validator finite_range(double lo, double hi);

// An option taking on|off, stored as a bool (e.g. --shadows on). Its default is the bool's
// value when added.
CLI::Option* add_on_off_option(CLI::App& app, const std::string& name, bool& value,
                               const std::string& help);

// Adds a paragraph to the end of `app`'s --help text (its footer), after what is there.
void add_help_paragraph(CLI::App& app, const std::string& paragraph);

// Adds --width and --height to `app` (each 1 .. k_max_image_side) and refuses, after parsing,
// an image of more than k_max_image_pixels pixels. Sets the app's final callback.
void add_image_size_options(CLI::App& app, int& width, int& height);

// Adds the image size (add_image_size_options), --output, --backend, --frames and --json to
// `app`.
void add_common_options(CLI::App& app, CommonOptions& options);

// Something the reader should know that does not stop the run, as one line on stderr:
// "warning: <what>", after whatever stdout has printed so far.
void warn(const std::string& what);

// Parses the command line and runs `body`. Prints "<program>: error: <message>" on any error
// and returns the exit code: 0 success, 1 runtime error, 2 bad usage.
int run_main(CLI::App& app, int argc, char** argv, const std::function<int()>& body);
// The same for a chapter's program: once parsed, an --output that names no .png, .pfm or .exr
// file, and a --json that could never be written, fail before any work is done.
int run_main(CLI::App& app, int argc, char** argv, const CommonOptions& options,
             const std::function<int()>& body);

} // namespace rt
