// Chapter 11: a moving scene path-traced where it moves. See moving_path.h.
#include "moving_path.h"

#include <string>

#include "rt/error.h"

namespace rt::ch11 {
namespace {

// The start's features, checked before anything is built.
unsigned moving_features(const PathScene& start) {
  if (!start.lights.triangles.empty())
    throw InputError("moving scene: " + std::to_string(start.lights.triangles.size()) +
                     " emitting triangles; a moving scene is lit by its sky and sun only");
  return features_used(start);
}

} // namespace

MovingPathRenderer::MovingPathRenderer(const PathScene& start, Backend backend, int detail,
                                       const ch04::Mesh* model)
    : PathRenderer(backend, moving_features(start)),
      frames_(backend, ch10::Builder::lbvh, detail, model),
      material_(backend, std::span<const int>(start.material)),
      materials_(backend, std::span<const PathMaterial>(start.materials)) {
  if (frames_.triangles() != std::ssize(start.mesh.triangles))
    throw InputError("moving scene: " + std::to_string(start.mesh.triangles.size()) +
                     " triangles given for a scene of " + std::to_string(frames_.triangles()));
  // [listing:moving_view]
  // The view is made once: every frame rewrites the arrays it points at, never moves them.
  // The tree's node count is the collapse's capacity (the traversal only asks whether it is
  // zero), so it too holds for every frame.
  view_ = {};
  view_.tree = frames_.wide_view();
  view_.mesh = frames_.mesh();
  view_.material = material_.data();
  view_.materials = materials_.data();
  view_.environment = start.environment; // no light table: the scene has no emitters
  // [/listing:moving_view]
  move_to(0.0);
}

ch10::FrameParts MovingPathRenderer::move_to(double time) {
  const ch10::FrameParts parts = frames_.move(time, ch10::Update::rebuild);
  empty_sums(); // the samples so far measured another picture
  return parts;
}

} // namespace rt::ch11
