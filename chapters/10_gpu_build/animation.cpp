// Chapter 10: the moving scene and its frames. See animation.h.
#include "animation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

#include "motion.h"
#include "moving_frames.h"
#include "rt/backend_array.h"
#include "rt/cpu_progress.h"
#include "rt/error.h"

namespace rt::ch10 {
namespace {

// [listing:rippling_torus]
// The torus around the y axis, its tube's radius rippling with time (torus_vertex, motion.h,
// in double, each vertex then rounded to float).
ch04::Mesh rippling_torus(double time, int detail) {
  const int around = detail, across = detail / 2;
  ch04::Mesh torus;
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < across; ++j)
      torus.vertices.push_back(torus_vertex(i, j, around, across, time).as<float>());
  const auto at = [&](int i, int j) { return (i % around) * across + (j % across); };
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < across; ++j) {
      torus.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j)});
      torus.triangles.push_back({at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
    }
  return torus;
}
// [/listing:rippling_torus]

} // namespace

ch04::Mesh fit_moving_model(ch04::Mesh model) {
  if (model.triangles.empty()) throw InputError("--moving --scene: the model has no triangles");
  Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const Vec3f& v : model.vertices) {
    lo = {std::min(lo.x, double(v.x)), std::min(lo.y, double(v.y)),
          std::min(lo.z, double(v.z))};
    hi = {std::max(hi.x, double(v.x)), std::max(hi.y, double(v.y)),
          std::max(hi.z, double(v.z))};
  }
  const double side = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  const double scale = side > 0.0 ? 5.0 / side : 1.0;
  const Vec3d from{0.5 * (lo.x + hi.x), lo.y, 0.5 * (lo.z + hi.z)};
  const Vec3d to{0.0, -1.6 + 1.5 * double(k_wave_height), 0.0}; // above the floor's top
  for (Vec3f& v : model.vertices) v = (to + (v.as<double>() - from) * scale).as<float>();
  return model;
}

// [listing:waving_model]
ch04::Mesh waving_model(const ch04::Mesh& fitted, double time) {
  ch04::Mesh moved = fitted;
  for (Vec3f& v : moved.vertices)
    v.y = float(wave_height(double(v.x), double(v.y), double(v.z), time));
  return moved;
}
// [/listing:waving_model]

ch05::ObjMesh moving_scene_at(double time, int detail, const ch04::Mesh* model) {
  if (detail < 8 || detail > k_max_moving_detail)
    throw InputError("--detail " + std::to_string(detail) + ": the torus takes 8 to " +
                     std::to_string(k_max_moving_detail) +
                     " (the scene within 10 million triangles)");
  ch05::ObjMesh scene;
  scene.geometry = model ? waving_model(*model, time) : rippling_torus(time, detail);
  scene.material_ids.assign(scene.geometry.triangles.size(), 0);
  for (int k = 0; k < 4; ++k) { // the spheres: rigid motion, each on its own orbit
    const ch04::Mesh sphere = ch04::make_icosphere(3, sphere_centre(k, time), 0.45);
    ch04::append_mesh(scene.geometry, sphere);
    scene.material_ids.insert(scene.material_ids.end(), sphere.triangles.size(), 1 + k);
  }
  const ch04::Mesh floor = ch04::make_box({-6.0, -1.9, -6.0}, {6.0, -1.6, 6.0}, 4);
  ch04::append_mesh(scene.geometry, floor);
  scene.material_ids.insert(scene.material_ids.end(), floor.triangles.size(), 5);
  scene.object_count = 6;
  return scene;
}

ch03::CameraSpec moving_scene_camera() {
  ch03::CameraSpec camera;
  camera.eye = {0.0, 5.0, 9.5};
  camera.target = {0.0, -0.3, 0.0};
  camera.fov_degrees = 45.0;
  return camera;
}

const char* to_string(Update update) { return update == Update::rebuild ? "rebuild" : "refit"; }

Update parse_update(const std::string& name) {
  if (name == "rebuild") return Update::rebuild;
  if (name == "refit") return Update::refit;
  throw UsageError("--update " + name + ": rebuild or refit");
}

// [listing:frame_loop]
AnimationResult run_animation(const AnimationOptions& options) {
  AnimationResult result;
  result.frames.resize(options.updates.size());
  const ch03::Camera<float> camera = ch03::make_camera<float>(options.camera, options.extent);
  BackendArray<Rgba8> pixels(options.backend, options.extent.pixel_count());
  std::vector<std::unique_ptr<MovingFrames>> scenes; // one per update: each keeps its tree
  for (std::size_t u = 0; u < options.updates.size(); ++u)
    scenes.push_back(std::make_unique<MovingFrames>(options.backend, options.builder,
                                                    options.detail, options.model.get(),
                                                    options.collapse));
  const CpuWorkName work("moving scene");
  CpuProgress progress(options.frames, "frames");
  for (int frame = 0; frame < options.frames; ++frame) {
    progress.update(frame);
    for (std::size_t u = 0; u < options.updates.size(); ++u) {
      const auto start = std::chrono::steady_clock::now();
      const FrameParts parts =
          scenes[u]->frame(frame * options.seconds_per_frame, options.updates[u], camera,
                           options.extent, pixels.data());
      FrameFigures figures;
      figures.wall_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      figures.animate_ms = parts.animate_ms;
      figures.tree_ms = parts.tree_ms;
      figures.collapse_ms = parts.collapse_ms;
      figures.trace_ms = parts.render_ms;
      figures.sah_cost = scenes[u]->binary_tree().stats.sah_cost; // outside the frame's time
      result.frames[u].push_back(figures);
    }
  }
  result.triangles = scenes.front()->triangles();
  result.last_frame = Image(options.extent.width, options.extent.height);
  const std::vector<Rgba8> last = pixels.to_host();
  std::copy(last.begin(), last.end(), result.last_frame.pixels.begin());
  return result;
}
// [/listing:frame_loop]

std::string animation_csv(const AnimationOptions& options, const AnimationResult& result) {
  std::ostringstream out;
  out << "frame";
  for (const Update u : options.updates)
    out << "," << to_string(u) << "_animate_ms," << to_string(u) << "_tree_ms," << to_string(u)
        << "_collapse_ms," << to_string(u) << "_trace_ms," << to_string(u) << "_wall_ms,"
        << to_string(u) << "_sah_cost";
  out << "\n";
  for (int frame = 0; frame < options.frames; ++frame) {
    out << frame;
    for (const std::vector<FrameFigures>& update : result.frames) {
      const FrameFigures& f = update[frame];
      out << "," << f.animate_ms << "," << f.tree_ms << "," << f.collapse_ms << ","
          << f.trace_ms << "," << f.wall_ms << "," << f.sah_cost;
    }
    out << "\n";
  }
  return out.str();
}

} // namespace rt::ch10
