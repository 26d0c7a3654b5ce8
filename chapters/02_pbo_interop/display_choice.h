// Chapter 02: window or not. --window insists on a window, --headless never opens one, and by
// default a window opens when there is a display; without one the program says so and
// renders headless. Every later chapter's program chooses this way.
#pragma once

#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "rt/launch.h"
#include "viewer.h"

namespace rt::ch02 {

struct DisplayChoice {
  bool headless = false; // --headless
  bool window = false;   // --window
};

// Adds --headless (described by `headless_help`: what the program does without a window) and
// --window; the two exclude each other.
void add_display_flags(CLI::App& app, DisplayChoice& choice, const std::string& headless_help);

// The viewer the choice asks for, or null for headless: without a display it prints a notice
// and returns null, unless --window insisted (then the DisplayError goes on).
std::unique_ptr<Viewer> open_viewer(const DisplayChoice& choice, Extent size,
                                    const std::string& title);

// The report's "mode" line, which says what its times measure.
inline constexpr const char* k_window_mode =
    "window (frame time: render + upload + draw, glFinish)";
inline constexpr const char* k_headless_mode = "headless (GPU: CUDA events; CPU: steady clock)";

} // namespace rt::ch02
