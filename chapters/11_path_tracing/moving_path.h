// Chapter 11: a moving scene path-traced where it moves. Chapter 10's frames (moving_frames.h)
// keep the scene on the backend: the rest pose goes there once, and each frame a pass moves
// the vertices, the LBVH is built from them and collapsed to the 4-wide tree, all in arrays
// made once. This renderer points the kernels' view at those arrays when it is made; a frame
// rewrites them in place, and only the sums start again. Nothing crosses to the host.
#pragma once

#include <vector>

#include "moving_frames.h"
#include "path_render.h"

namespace rt::ch11 {

// [listing:moving_path_renderer]
class MovingPathRenderer : public PathRenderer {
public:
  // `start` is moving_path_scene(0, detail, model) with the environment that lights it;
  // `model` the fitted model (ch10::fit_moving_model) or null for the torus. The scene is
  // placed at time 0. What else depends on the vertices: the light table, which a scene
  // without emitters leaves empty at every time (a start that emits is refused: its table
  // would have to move too); and the normals, which the paths take from each hit triangle's
  // vertices as they are. Throws InputError for a start that emits, or that has another
  // triangle count than the scene the frames make.
  MovingPathRenderer(const PathScene& start, Backend backend, int detail,
                     const ch04::Mesh* model = nullptr);

  // The scene at `time` (seconds): chapter 10's passes move the vertices, build the LBVH and
  // collapse it, on the backend and in place; the sums are emptied (the camera and first
  // sample kept). Returns the three parts' times (GPU: CUDA events; render_ms is 0).
  ch10::FrameParts move_to(double time);

  // What the last move made, copied to the host (for tests).
  std::vector<Vec3f> vertices() const { return frames_.vertices(); }
  ch09::Wide4PackedBvh wide_tree() const { return frames_.wide_tree(); }

private:
  ch10::MovingFrames frames_;  // vertices, tree and collapse, on the backend
  BackendArray<int> material_; // per triangle: uploaded once, never moves
  BackendArray<PathMaterial> materials_;
};
// [/listing:moving_path_renderer]

} // namespace rt::ch11
