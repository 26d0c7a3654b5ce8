// Chapter 10: scenes that move, and what keeping their tree up to date costs. A torus whose
// surface ripples (every vertex moves every frame) and spheres that orbit it, over a floor;
// each frame either builds its tree again or refits last frame's, then renders chapter 06's
// shaded image through it. Rebuilding costs a build per frame; refitting costs less, but the
// boxes of a refitted tree grow apart from the geometry they were made for, and every ray pays
// for it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "builders.h"
#include "camera_spec.h"
#include "motion.h"
#include "obj_loader.h"
#include "rt/backend.h"
#include "rt/image.h"
#include "rt/launch.h"

namespace rt::ch10 {

// The moving scene's triangles at `detail`: the torus's (detail segments around, detail / 2
// across, two triangles each: detail^2 for an even detail), four icospheres of 1 280 and the
// floor's 6 faces of 4 x 4 cells.
constexpr long long moving_scene_triangles(int detail) {
  return 2LL * detail * (detail / 2) + 4 * 1280 + 6 * 4 * 4 * 2;
}

// The largest detail: the scene within the 10 million triangles a model may have (chapter
// 05's LoadLimits; sqrt(10^7) = 3162 less the spheres and the floor), 9 994 072 triangles.
// Chapter 11's moving scene is bounded by it too.
inline constexpr int k_max_moving_detail = 3161;
static_assert(moving_scene_triangles(k_max_moving_detail) <= ch05::LoadLimits{}.max_triangles &&
              moving_scene_triangles(k_max_moving_detail + 1) >
                  ch05::LoadLimits{}.max_triangles);

// The scene at `time` (seconds): the rippling torus of detail^2 triangles (detail segments
// around, detail / 2 across, two triangles each), four orbiting icospheres and the floor.
// Every time gives the same triangles in the same order, only the vertices move. The reference
// of the frames made on the backend (moving_frames.h). Throws InputError for a detail outside
// 8..k_max_moving_detail.
// With a `model` (fitted by fit_moving_model) in the torus's place: the model waving
// (waving_model), the same spheres and floor around it.
ch05::ObjMesh moving_scene_at(double time, int detail, const ch04::Mesh* model = nullptr);

// A model of the reader's moved and scaled into the torus's place: centred over the floor,
// its largest side 5 units long, its lowest point just above the floor. Throws InputError
// for a model with no triangles.
ch04::Mesh fit_moving_model(ch04::Mesh model);

// The fitted model at `time`: every vertex lifted by a wave that runs across the floor,
// k_wave_height * sin(2 x + 1.5 z - 2 time) (wave_height, motion.h): each moves by its own
// amount, as the torus's do.
ch04::Mesh waving_model(const ch04::Mesh& fitted, double time);

// The animation's pace: 30 frames a second of scene time.
inline constexpr double k_seconds_per_frame = 1.0 / 30.0;

// A camera that sees the whole animation.
ch03::CameraSpec moving_scene_camera();

// How the tree follows the motion: built again every frame, or built once and refitted.
enum class Update { rebuild, refit };
const char* to_string(Update update);
Update parse_update(const std::string& name); // "rebuild" or "refit"; UsageError otherwise

struct AnimationOptions {
  Backend backend = Backend::cpu; // resolved
  Builder builder = Builder::lbvh;
  CollapseRule collapse = CollapseRule::sah;
  std::vector<Update> updates{Update::rebuild, Update::refit};
  int frames = 60;
  double seconds_per_frame = k_seconds_per_frame;
  int detail = 316;                        // about 100k triangles in the torus
  std::shared_ptr<const ch04::Mesh> model; // fitted: in the torus's place; null: the torus
  Extent extent{1920, 1080};
  ch03::CameraSpec camera = moving_scene_camera();
};

// One frame of one update, made on the backend (moving_frames.h): the vertices moved, the tree
// built or refitted, collapsed to 4-wide, and the shaded frame traced through it (GPU: CUDA
// events between the parts; CPU: wall time); the whole frame's wall time; and the binary
// tree's SAH cost.
struct FrameFigures {
  double animate_ms = 0, tree_ms = 0, collapse_ms = 0, trace_ms = 0, wall_ms = 0, sah_cost = 0;
};

struct AnimationResult {
  std::vector<std::vector<FrameFigures>> frames; // per update of AnimationOptions::updates
  long long triangles = 0;
  Image last_frame; // the last update's last frame
};

// The frames, each update's one after the other; every few seconds a progress line on stderr
// (rt/cpu_progress.h), "moving scene: 37% (22 of 60 frames), 15 s".
AnimationResult run_animation(const AnimationOptions& options);

// The figures as CSV, one line per frame: frame, then animate, tree, collapse, trace and wall
// ms and the SAH cost of each update, in the options' order.
std::string animation_csv(const AnimationOptions& options, const AnimationResult& result);

} // namespace rt::ch10
