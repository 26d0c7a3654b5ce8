// Chapter 03: the interactive window every chapter from here on opens with --window. Each
// frame the renderer draws the current camera straight into OpenGL's pixel buffer (the
// interop of chapter 02) on the GPU, or into host memory on the CPU; the mouse and keys move
// the camera (orbit_controls.h).
#pragma once

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "camera_spec.h"
#include "display_choice.h"
#include "rt/backend.h"
#include "rt/image.h"
#include "rt/timer.h"
#include "viewer.h"

namespace rt::ch03 {

// Draws one frame of `camera` into `pixels` (device memory on the GPU backend).
using FrameRenderer = std::function<void(Backend backend, const CameraSpec& camera,
                                         Extent extent, Rgba8* pixels)>;
// The same, with each pixel's linear colour (radiance, before the picture's tone curve) into
// `radiance` when it is not null.
using LinearFrameRenderer = std::function<void(Backend backend, const CameraSpec& camera,
                                               Extent extent, Rgba8* pixels, Vec3f* radiance)>;

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

  Extent extent() const { return {last_screen.width, last_screen.height}; }
};

// Window or not (chapter 02's choice): --headless, --window, or a window when there is a
// display.
using ch02::DisplayChoice;
using ch02::k_headless_mode;
using ch02::k_window_mode;
using ch02::open_viewer;

// Adds --headless and --window, and a footer that lists the window's controls (before any
// footer the program has set).
void add_display_options(CLI::App& app, DisplayChoice& choice);

WindowResult run_window(ch02::Viewer& viewer, Backend backend, const CameraSpec& start,
                        const WindowSettings& settings, const FrameRenderer& render);

} // namespace rt::ch03
