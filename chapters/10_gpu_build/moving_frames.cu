// Chapter 10: the moving scene's frames on the backend. See moving_frames.h.
#include "moving_frames.h"

#include <array>
#include <chrono>
#include <optional>

#include "build_passes.cuh"
#include "builders.h"
#include "gpu_build.h"
#include "motion.h"
#include "rt/timer.h"
#include "shaded_render.h"
#include "shaded_scene.h"
#include "wide_collapse.h"
#include "wide_render.h"

namespace rt::ch10 {
namespace {

using namespace passes;

// Each vertex of the scene at `time`, computed alone, by motion.h's templates in float (the
// host's reference scene takes them in double): the torus's from its place in the grid or a
// model's lifted by the wave, the spheres' as their rest offsets around their orbiting
// centres, the floor's where it rests.
struct MoveVertices {
  const Vec3f*
      rest;   // model: fitted; sphere vertices: offsets from the centre; floor: positions
  int detail; // the torus: detail * (detail / 2) vertices, first
  int model_vertices; // > 0: a waving model's vertices come first instead
  int sphere_vertices;
  float time;
  Vec3f* vertices;
  RT_HD void operator()(int v) const {
    const int around = detail, across = detail / 2;
    const int torus = model_vertices > 0 ? model_vertices : around * across;
    if (v < model_vertices) {
      const Vec3f r = rest[v];
      vertices[v] = {r.x, wave_height(r.x, r.y, r.z, time), r.z};
      return;
    }
    if (v < torus) {
      vertices[v] = torus_vertex(v / across, v % across, around, across, time);
      return;
    }
    const int k = (v - torus) / sphere_vertices;
    if (k < 4) {
      vertices[v] = sphere_centre(k, time) + rest[v];
      return;
    }
    vertices[v] = rest[v];
  }
};

} // namespace

struct MovingFrames::State {
  Backend backend;
  Builder builder;
  int detail, model_vertices, sphere_vertices;
  // At time 0: triangles, materials, lights (placed for the first frame's bounds, and kept);
  // the vertices move. Its vertex normals would not follow them, so the frames are shaded
  // with each triangle's own normal (and shadows).
  ch06::ShadedScene scene;
  unsigned features;
  BackendArray<Vec3f> rest, vertices;
  BackendArray<IndexedTriangle> triangles;
  std::optional<ch06::DeviceShadedScene> d_scene; // for the shaded frames (a renderer of its
                                                  // own that calls move() uploads none)
  LbvhOnBackend lbvh;
  WideCollapse collapse;
  std::optional<TreeArrays> host_built; // another builder's tree, built on the host
  BackendClock clock;                   // marks between a frame's parts
  bool built = false;

  State(Backend b, Builder which, int d, int model_count, int per_sphere,
        const ch05::ObjMesh& start, std::vector<Vec3f> rest_pose, CollapseRule rule)
      : backend(b), builder(which), detail(d), model_vertices(model_count),
        sphere_vertices(per_sphere), scene(ch06::scene_from_obj(start, {})),
        features(ch06::features_used(scene, false, true)),
        rest(b, std::span<const Vec3f>(rest_pose)),
        vertices(b, std::span<const Vec3f>(scene.mesh.vertices)),
        triangles(b, std::span<const IndexedTriangle>(scene.mesh.triangles)), lbvh(b, mesh()),
        collapse(b, mesh().triangle_count, k_wide_leaf_triangles, rule), clock(b, 5) {}

  TreeArrays& tree() { return host_built ? *host_built : lbvh.tree(); }

  // The tree for the vertices as they are now: the LBVH's passes, or another builder on the
  // host from the vertices copied there.
  void build() {
    if (builder == Builder::lbvh) {
      lbvh.build();
      return;
    }
    ch04::Mesh now = scene.mesh;
    now.vertices = vertices.to_host();
    host_built = upload_tree(backend, build_tree(builder, backend, now).bvh);
  }

  // The frame's first parts, marks 0 to 3 between them: the vertices moved to `time`, the
  // tree built or refitted, collapsed. Queued; nothing waits.
  void advance(double time, Update update) {
    clock.mark(0);
    for_each_index(backend, static_cast<int>(vertices.size()),
                   MoveVertices{rest.data(), detail, model_vertices, sphere_vertices,
                                float(time), vertices.data()});
    clock.mark(1);
    if (update == Update::refit && built)
      refit_tree(backend, tree(), mesh());
    else
      build();
    built = true;
    clock.mark(2);
    collapse.run(tree());
    clock.mark(3);
  }
  // Their times, read after the marks (on the GPU, waiting for the last).
  FrameParts parts() {
    return {clock.milliseconds_between(0, 1), clock.milliseconds_between(1, 2),
            clock.milliseconds_between(2, 3), 0.0};
  }

  MeshView mesh() {
    return {vertices.data(), triangles.data(), static_cast<int>(triangles.size())};
  }
  ch06::SceneView scene_view() {
    ch06::SceneView view = d_scene ? d_scene->view() : ch06::host_view(scene, features);
    view.mesh = mesh();
    return view;
  }
};

MovingFrames::MovingFrames(Backend backend, Builder builder, int detail,
                           const ch04::Mesh* model, CollapseRule rule) {
  const ch05::ObjMesh start = moving_scene_at(0.0, detail, model);
  // Rest pose: a model as fitted, the spheres' vertices as offsets from their centres, the
  // floor as it lies.
  std::vector<Vec3f> rest = start.geometry.vertices;
  if (model) std::copy(model->vertices.begin(), model->vertices.end(), rest.begin());
  const std::vector<Vec3f> sphere = ch04::make_icosphere(3, {0.0, 0.0, 0.0}, 0.45).vertices;
  const std::size_t first =
      model ? model->vertices.size() : std::size_t(detail) * std::size_t(detail / 2);
  for (int k = 0; k < 4; ++k)
    std::copy(sphere.begin(), sphere.end(), rest.begin() + first + k * sphere.size());
  state_ = std::make_unique<State>(
      backend, builder, detail, model ? static_cast<int>(model->vertices.size()) : 0,
      static_cast<int>(sphere.size()), start, std::move(rest), rule);
}

MovingFrames::~MovingFrames() = default;

FrameParts MovingFrames::frame(double time, Update update, const ch03::Camera<float>& camera,
                               Extent extent, Rgba8* pixels) {
  State& s = *state_;
  if (s.backend == Backend::gpu && !s.d_scene) s.d_scene.emplace(s.scene, s.features);
  s.advance(time, update);
  ch09::render_wide_shaded(s.backend, s.features,
                           ch09::with_wide(s.scene_view(), s.collapse.view()), camera, extent,
                           pixels);
  s.clock.mark(4);
  FrameParts parts = s.parts();
  parts.render_ms = s.clock.milliseconds_between(3, 4);
  return parts;
}

FrameParts MovingFrames::move(double time, Update update) {
  state_->advance(time, update);
  return state_->parts();
}

ch04::MeshView MovingFrames::mesh() const { return state_->mesh(); }

ch09::Wide4PackedBvh::View MovingFrames::wide_view() const { return state_->collapse.view(); }

std::vector<Vec3f> MovingFrames::vertices() const { return state_->vertices.to_host(); }

ch07::Bvh MovingFrames::binary_tree() const {
  TreeArrays& tree = state_->tree();
  ch07::Bvh bvh;
  bvh.nodes = tree.nodes.to_host();
  bvh.triangles = tree.triangles.to_host();
  bvh.triangle_ids = tree.triangle_ids.to_host();
  bvh.bounds = root_bounds(bvh);
  bvh.options.method = ch07::SplitMethod::median;
  bvh.options.max_leaf_size = 1;
  fill_stats(bvh);
  return bvh;
}

ch09::Wide4PackedBvh MovingFrames::wide_tree() const { return state_->collapse.to_host(); }

long long MovingFrames::triangles() const {
  return static_cast<long long>(state_->triangles.size());
}

} // namespace rt::ch10
