// Chapter 10: the program's --moving mode. In the window the scene moves as it is shown, its
// tree rebuilt or refitted for every frame drawn; headless it runs the animation's frames with
// both updates (or the one asked for), prints each frame's figures, and writes the report, the
// CSV of the frames and the last frame's image.
#pragma once

#include <string>

#include "animation.h"
#include "program.h"

namespace rt::ch10 {

struct MovingOptions {
  AnimationOptions animation; // backend and extent are set from the program's options
  std::string csv_path;       // --animation-csv; empty: none
  std::string model_name;     // the file name of animation.model, for the report
};

// Runs the mode on the resolved backend; returns the exit code.
int run_moving_program(const ch03::ProgramOptions& program, MovingOptions moving,
                       Backend backend);

} // namespace rt::ch10
