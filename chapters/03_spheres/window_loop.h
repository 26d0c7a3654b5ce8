// Chapter 03: the interactive window every chapter from here on opens with --window. Each
// frame the renderer draws the current camera straight into OpenGL's pixel buffer (the
// interop of chapter 02) on the GPU, or into host memory on the CPU; the mouse and keys move
// the camera (orbit_controls.h).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "camera_spec.h"
#include "rt/backend.h"
#include "rt/image.h"
#include "rt/timer.h"
#include "viewer.h"

namespace rt::ch03 {

// Draws one frame of `camera` into `pixels` (device memory on the GPU backend).
using FrameRenderer = std::function<void(Backend backend, const CameraSpec& camera,
                                         Extent extent, Rgba8* pixels)>;

struct WindowSettings {
  std::string title;       // the window title's prefix
  int scripted_frames = 0; // > 0: run this many frames without vsync, then close
  std::string screenshot_prefix = "screenshot"; // S writes <prefix>_<frame>.png
};

struct WindowResult {
  std::string path;  // "interop" or "host upload"
  Timing frame_time; // render + upload + draw, glFinish'ed
  Image last_screen; // what the window showed last
  CameraSpec camera; // the camera of that frame
  int frames = 0;
};

// Window or not: --window insists on one, --headless never opens one, and by default a window
// opens when there is a display.
struct DisplayChoice {
  bool headless = false;
  bool window = false;
};

// Adds --headless and --window, and a footer that lists the window's controls.
void add_display_options(CLI::App& app, DisplayChoice& choice);

// The viewer the choice asks for, or null for headless: without a display it prints a notice
// and returns null, unless --window insisted (then the DisplayError goes on).
std::unique_ptr<ch02::Viewer> open_viewer(const DisplayChoice& choice, Extent size,
                                          const std::string& title);

inline constexpr const char* k_window_mode =
    "window (frame time: render + upload + draw, glFinish)";
inline constexpr const char* k_headless_mode = "headless (GPU: CUDA events; CPU: steady clock)";

WindowResult run_window(ch02::Viewer& viewer, Backend backend, const CameraSpec& start,
                        const WindowSettings& settings, const FrameRenderer& render);

} // namespace rt::ch03
