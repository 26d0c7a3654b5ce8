// Chapter 02: three ways a frame reaches the window. The kernel writes OpenGL's pixel buffer
// directly (interop); the GPU renders into its own memory and the frame crosses the bus twice
// (copy); or the CPU renders and the frame is uploaded. The window shows the animation through
// each path in turn and times each one.
#pragma once

#include <string>
#include <vector>

#include "rt/backend.h"
#include "rt/image.h"
#include "rt/launch.h"
#include "rt/timer.h"
#include "viewer.h"

namespace rt::ch02 {

enum class DisplayPath { interop, copy, cpu };

const char* path_name(DisplayPath path);

// What one path showed: its frame times and the window's content at its last frame.
struct ShownPath {
  DisplayPath path;
  Timing frame_time; // render + upload + draw, glFinish'ed
  Image screen;      // what the window showed last
  Extent extent;     // the size the path rendered at
  int frame = 0;     // the animation frame on screen
  bool last = false; // the last of the paths
};

// Shows the animation through the paths `choice` names ("all", "interop", "copy" or "cpu"),
// P switching between them. With scripted_frames > 0 each path shows that many frames without
// vsync, and the window closes after the last path. Returns each path as it was left.
std::vector<ShownPath> show_display_paths(Viewer& viewer, Backend backend,
                                          const std::string& choice, int scripted_frames);

} // namespace rt::ch02
