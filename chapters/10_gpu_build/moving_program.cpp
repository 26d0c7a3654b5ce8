// Chapter 10: the program's --moving mode. See moving_program.h.
#include "moving_program.h"

#include <cstdio>
#include <iostream>
#include <optional>

#include "camera_cli.h"
#include "moving_frames.h"
#include "rt/output_file.h"
#include "rt/program_output.h"

namespace rt::ch10 {
namespace {

// Each frame's figures, one line per frame.
void print_frames(const AnimationOptions& animation, const AnimationResult& result) {
  for (int frame = 0; frame < animation.frames; ++frame) {
    std::cout << "frame " << frame;
    for (std::size_t u = 0; u < animation.updates.size(); ++u) {
      const FrameFigures& f = result.frames[u][frame];
      std::cout << (u == 0 ? ": " : "; ") << to_string(animation.updates[u]) << " "
                << format_fixed(f.tree_ms, 2) << " ms + collapse "
                << format_fixed(f.collapse_ms, 2) << " ms + frame "
                << format_fixed(f.trace_ms, 2) << " ms, SAH cost "
                << format_fixed(f.sah_cost, 1);
    }
    std::cout << "\n";
  }
}

// One row per update: mean tree and frame ms, and how far the SAH cost moved.
void add_rows(Report& report, const AnimationOptions& animation,
              const AnimationResult& result) {
  for (std::size_t u = 0; u < animation.updates.size(); ++u) {
    const std::vector<FrameFigures>& frames = result.frames[u];
    double animate = 0, tree = 0, collapse = 0, trace = 0, wall = 0;
    for (const FrameFigures& f : frames) {
      animate += f.animate_ms, tree += f.tree_ms, collapse += f.collapse_ms;
      trace += f.trace_ms, wall += f.wall_ms;
    }
    const double n = double(frames.size()), ms = (animate + tree + collapse + trace) / n;
    const double growth = frames.back().sah_cost / frames[0].sah_cost;
    report.add_row(
        {std::string(to_string(animation.builder)) + ", " + to_string(animation.updates[u]),
         to_string(animation.backend),
         ms,
         double(animation.extent.pixel_count()) / (ms * 1e3),
         format_fixed(animate / n, 2) + " ms animate + " + format_fixed(tree / n, 2) +
             " ms tree + " + format_fixed(collapse / n, 2) + " ms collapse + " +
             format_fixed(trace / n, 2) + " ms frame; " + format_fixed(1e3 * n / wall, 0) +
             " frames/s wall clock; SAH cost x" + format_fixed(growth, 3) +
             " by the last frame",
         {{"animate_ms", animate / n},
          {"tree_ms", tree / n},
          {"collapse_ms", collapse / n},
          {"trace_ms", trace / n},
          {"wall_fps", 1e3 * n / wall},
          {"sah_growth", growth}}});
  }
}

// The window's frames: each one a step of the animation made on the backend (moving_frames.h),
// its tree updated as the first of the options' updates says.
class WindowAnimation {
public:
  explicit WindowAnimation(const AnimationOptions& options) : options_(options) {}

  void render(Backend backend, const ch03::CameraSpec& spec, Extent extent, Rgba8* pixels) {
    if (!frames_)
      frames_.emplace(backend, options_.builder, options_.detail, options_.model.get(),
                      options_.collapse);
    frames_->frame(frame_++ * options_.seconds_per_frame, options_.updates.front(),
                   ch03::make_camera<float>(spec, extent), extent, pixels);
  }

private:
  const AnimationOptions& options_;
  int frame_ = 0;
  std::optional<MovingFrames> frames_;
};

// The animation's camera, and the command line's --eye, --target, --fov, --up and --camera
// where it gives them.
ch03::CameraSpec moving_camera(const ch03::ProgramOptions& program) {
  const ch03::CameraSpec framed = moving_scene_camera();
  ch03::CameraSpec camera = program.camera;
  if (!program.eye_given) camera.eye = framed.eye;
  if (!program.target_given) camera.target = framed.target;
  if (!program.fov_given) camera.fov_degrees = framed.fov_degrees;
  ch03::validate_camera(camera);
  return camera;
}

} // namespace

void check_moving_outputs(const MovingOptions& moving) {
  if (!moving.csv_path.empty()) check_output_path(moving.csv_path, "--animation-csv");
}

int run_moving_program(const ch03::ProgramOptions& program, MovingOptions moving,
                       Backend backend) {
  AnimationOptions& animation = moving.animation;
  animation.backend = backend;
  animation.extent = program.size_given() ? program.common.extent() : animation.extent;
  if (program.common.frames > 0) animation.frames = program.common.frames;
  check_moving_outputs(moving);
  animation.camera = moving_camera(program);
  const std::string builder = to_string(animation.builder);
  Report report =
      start_report("Chapter 10: a moving scene, its tree updated every frame", "Mpix/s",
                   "the tree's SAH cost against the first frame's", backend);
  WindowAnimation shown(animation);
  const ch03::ProgramParts parts{
      .chapter = "ch10",
      .window_title = std::string("moving scene, tree ") + to_string(animation.updates.front()),
      .camera = animation.camera,
      .render = [&](Backend b, const ch03::CameraSpec& spec, Extent extent,
                    Rgba8* pixels) { shown.render(b, spec, extent, pixels); },
      .window_row =
          [&](const ch03::WindowResult& result) {
            return ch03::window_fps_row("moving scene", backend, result);
          },
      .window_context = {{"tree", builder + ", " + to_string(animation.updates.front()) +
                                      " every frame drawn, collapsed by the " +
                                      to_string(animation.collapse) + " rule"}},
  };
  if (ch03::show_in_window(program, backend, parts, report)) {
    finish_report(report, program.common);
    return 0;
  }
  const AnimationResult result = run_animation(animation);
  report.add_context(
      "scene",
      (animation.model ? "waving " + moving.model_name : std::string("rippling torus")) +
          ", four orbiting spheres and a floor, " + group_digits(result.triangles) +
          " triangles, " + std::to_string(animation.frames) + " frames");
  report.add_context("tree", builder +
                                 (animation.updates.size() == 1
                                      ? std::string(", ") + to_string(animation.updates[0])
                                      : ", rebuilt and refitted") +
                                 ", collapsed by the " + to_string(animation.collapse) +
                                 " rule");
  print_frames(animation, result);
  add_rows(report, animation, result);
  if (!moving.csv_path.empty()) {
    const std::string csv = animation_csv(animation, result);
    write_output_file(moving.csv_path, "--animation-csv",
                      [&](std::FILE* file) { std::fputs(csv.c_str(), file); });
    std::cout << "wrote " << moving.csv_path << "\n";
  }
  if (!program.common.output.empty()) {
    write_image(program.common.output, result.last_frame);
    std::cout << "wrote " << program.common.output << " (the last frame)\n";
  }
  finish_report(report, program.common);
  return 0;
}

} // namespace rt::ch10
