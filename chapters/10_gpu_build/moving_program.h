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

// The mode's checks that need no work, for the program to make before any (a model loaded
// for --scene): --animation-csv's path (rt::check_output_path). Throws OutputError.
void check_moving_outputs(const MovingOptions& moving);

// Runs the mode on the resolved backend, through the animation's camera where the command
// line sets none (its --eye, --target, --fov, --up and --camera where it does); returns the
// exit code. Checks its outputs again (check_moving_outputs).
int run_moving_program(const ch03::ProgramOptions& program, MovingOptions moving,
                       Backend backend);

} // namespace rt::ch10
