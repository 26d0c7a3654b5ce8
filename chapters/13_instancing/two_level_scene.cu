// Chapter 13: the scene of instances on a backend, and the passes over it. See
// two_level_scene.h.
#include "two_level_scene.h"

#include <optional>

#include "gpu_build.h"
#include "rt/backend_array.h"
#include "rt/error.h"
#include "shade.h"
#include "spawn.h"
#include "trace.h"
#include "wide_collapse.h"

namespace rt::ch13 {

using ch07::BvhNode;

namespace {

// [listing:move_instances]
// One frame of the moving scene, an instance per item: its transform made again from its spin
// for the frame's time (in double), both directions rounded to float, and the double one kept
// for the boxes of its entries...
struct MoveInstances {
  const Spin* spins;
  double seconds;
  Instance* instances;
  AffineD* to_world;
  RT_HD void operator()(int k) const {
    const AffineD placed = spin_transform(spins[k], seconds);
    to_world[k] = placed;
    instances[k] = placed_instance(placed, instances[k].mesh, instances[k].mask);
  }
};

// ... then an entry per item: its subtree's box taken to the world by its instance.
struct BoxEntries {
  const TopEntry* entries;
  const Aabb* object_boxes; // of each entry's subtree, in its mesh's space
  const AffineD* to_world;
  Aabb* boxes;
  RT_HD void operator()(int e) const {
    boxes[e] = world_box(object_boxes[e], to_world[entries[e].instance]);
  }
};
// [/listing:move_instances]

// [listing:walk_kernel]
// The walks' kernels: for_each_index's, with a register budget. The two-level walk keeps two
// walks' state (79 registers nested, 72 to 80 in one loop), so only 24 warps fit on a
// multiprocessor, where chapter 09's one-tree walk, at 56 registers, fits 36; and a walk
// waits on memory most of its time. __launch_bounds__(256, 4) asks the compiler to fit four
// blocks of 256 threads, so at most 64 registers: 32 warps. Measured on an H200 (appendix
// C4): up to 11% faster than no bound (one row 1% slower); 48 registers (five blocks) spill the
// one loop's state to local memory and cost it 26 to 47%.
constexpr int k_walk_block = 256;
constexpr int k_walk_min_blocks = 4;
template <class Fn>
__global__ void __launch_bounds__(k_walk_block, k_walk_min_blocks)
    walk_kernel(int count, Fn fn) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < count) fn(i);
}
template <class Fn> void for_each_ray(Backend backend, int count, Fn fn) {
  if (backend != Backend::gpu || count <= 0) {
    for_each_index(backend, count, fn);
    return;
  }
  walk_kernel<<<blocks_to_cover(count, k_walk_block), k_walk_block>>>(count, fn);
  RT_CUDA_CHECK_LAUNCH("walk_kernel");
}
// [/listing:walk_kernel]

template <Query kQuery, TopLayout kTop> struct TraceRays {
  TwoLevelView scene;
  const RayF* rays;
  InstanceHit* hits;
  RT_HD void operator()(int i) const {
    hits[i] = trace_two_level<kQuery, kTop>(scene, rays[i]);
  }
};

// [listing:shade_instance]
// A pixel of the shaded image: the closest hit's triangle taken to the world by its instance,
// its normal turned to face the ray, the sun's light if the shadow ray (any hit, through both
// levels) reaches it, and a little sky light everywhere. Pixels go to threads in tiles of 8 x 4
// (rt::PixelTiles), so a warp's rays start close together.
template <TopLayout kTop> struct ShadePixels {
  TwoLevelView scene;
  ShadeView shade;
  ch03::Camera<float> camera;
  PixelTiles tiles;
  Rgba8* pixels;
  RT_HD void operator()(int number) const {
    int x = 0, y = 0;
    if (!tiles.pixel(unsigned(number), x, y)) return; // past the image's edge
    const int index = y * tiles.width + x;
    const RayF ray = camera.ray_through_pixel(x, y);
    const InstanceHit hit = trace_two_level<Query::closest, kTop>(scene, ray);
    Vec3f colour{0.55f, 0.7f, 0.9f}; // the sky
    if (hit.instance >= 0) {
      const Instance& instance = scene.instances[hit.instance];
      const ch04::TriangleF local = shade.meshes[instance.mesh].triangle(hit.triangle);
      const Affine& m = instance.to_world;
      const Vec3f a = m.point(local.v0), b = m.point(local.v1), c = m.point(local.v2);
      const Vec3f p = a * (1.0f - hit.u - hit.v) + b * hit.u + c * hit.v;
      const Vec3f n = ch06::faced(ch06::unit_or(cross(b - a, c - a), Vec3f{0.0f, 1.0f, 0.0f}),
                                  ray.direction * -1.0f);
      const float facing = dot(n, shade.to_sun);
      float sun = 0.0f;
      if (facing > 0.0f) {
        const RayF shadow{ch03::offset_ray_origin(p, n), shade.to_sun};
        sun = trace_two_level<Query::any, kTop>(scene, shadow).instance < 0 ? facing : 0.0f;
      }
      colour = shade.albedo[hit.instance] * (0.15f + 0.85f * sun);
    }
    pixels[index] = ch03::to_rgba8(colour);
  }
};
// [/listing:shade_instance]

} // namespace

struct TwoLevelScene::Arrays {
  Backend backend;
  int instance_count, entry_count;
  std::vector<BackendArray<ch09::WideNode<4>>> bottom_nodes;
  std::vector<BackendArray<ch09::PackedTriangles::Record>> bottom_triangles;
  std::vector<BackendArray<Vec3f>> vertices;
  std::vector<BackendArray<ch04::IndexedTriangle>> triangles;
  BackendArray<BottomView> bottom_views;
  BackendArray<ch04::MeshView> mesh_views;
  BackendArray<Instance> instances;
  BackendArray<AffineD> to_world;
  BackendArray<TopEntry> entries;
  BackendArray<Aabb> entry_object_boxes, boxes;
  BackendArray<Vec3f> albedo;
  BackendArray<Spin> spins;
  ch10::LbvhOverBoxes top;
  TopLayout layout;
  std::optional<ch10::WideCollapse> wide_top; // the wide layout's
  double bottom_bytes = 0.0;

  Arrays(Backend b, int instances, int entries, TopLayout l)
      : backend(b), instance_count(instances), entry_count(entries), top(b, entries),
        layout(l) {
    // Leaves of one entry, collapsed by the depth rule: the top level is built again every
    // frame, and on an H200 the sah rule's better top level (17.9 top-level nodes a camera ray
    // in the dragon forest, against 19.4) saved the walk 1% there and cost the build 0.07 ms,
    // and 0.57 ms for a million instances (1.48 ms against 0.91): book 13, "Tiles, and the
    // top level's collapse".
    if (l != TopLayout::binary) wide_top.emplace(b, entries, 1, ch10::CollapseRule::depth);
  }
};

TwoLevelScene::TwoLevelScene(Backend backend, const InstanceScene& scene,
                             const BottomLevel& bottom, std::vector<Spin> spins,
                             TopLayout top) {
  const std::vector<Instance> instances = make_instances(scene);
  if (instances.empty()) throw InputError("a scene of instances needs at least one instance");
  if (spins.size() > instances.size()) throw InputError("more spins than instances");
  // The top level's entries: each instance's subtrees (its mesh's root where not opened).
  std::vector<TopEntry> entries;
  std::vector<Aabb> object_boxes, boxes;
  std::vector<AffineD> to_world;
  for (std::size_t k = 0; k < scene.placements.size(); ++k) {
    const Placement& p = scene.placements[k];
    to_world.push_back(p.to_world);
    const std::vector<int>& nodes = bottom.open_nodes.at(p.mesh);
    for (std::size_t e = 0; e < nodes.size(); ++e) {
      entries.push_back({static_cast<int>(k), nodes[e]});
      object_boxes.push_back(bottom.open_boxes[p.mesh][e]);
      boxes.push_back(world_box(object_boxes.back(), p.to_world));
    }
  }
  if (entries.size() > static_cast<std::size_t>(k_max_instances))
    throw InputError(std::to_string(entries.size()) + " top-level entries: at most " +
                     std::to_string(k_max_instances) + " (open fewer levels)");
  arrays_ = std::make_unique<Arrays>(backend, static_cast<int>(instances.size()),
                                     static_cast<int>(entries.size()), top);
  Arrays& a = *arrays_;
  std::vector<BottomView> views;
  std::vector<ch04::MeshView> meshes;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const ch09::Wide4PackedBvh& tree = bottom.trees.at(m);
    a.bottom_nodes.emplace_back(backend, std::span(tree.nodes));
    a.bottom_triangles.emplace_back(backend, std::span(tree.triangles));
    a.vertices.emplace_back(backend, std::span(scene.meshes[m].vertices));
    a.triangles.emplace_back(backend, std::span(scene.meshes[m].triangles));
    BottomView view = backend == Backend::cpu ? tree.view() : BottomView{};
    view.nodes = a.bottom_nodes.back().data();
    view.triangles = a.bottom_triangles.back().data();
    view.node_count = static_cast<int>(tree.nodes.size());
    views.push_back(view);
    meshes.push_back({a.vertices.back().data(), a.triangles.back().data(),
                      static_cast<int>(scene.meshes[m].triangles.size())});
    a.bottom_bytes += double(tree.nodes.size() * sizeof(tree.nodes[0]) +
                             tree.triangles.size() * sizeof(tree.triangles[0]));
  }
  a.bottom_views = BackendArray<BottomView>(backend, std::span<const BottomView>(views));
  a.mesh_views = BackendArray<ch04::MeshView>(backend, std::span<const ch04::MeshView>(meshes));
  a.instances = BackendArray<Instance>(backend, std::span<const Instance>(instances));
  a.to_world = BackendArray<AffineD>(backend, std::span<const AffineD>(to_world));
  a.entries = BackendArray<TopEntry>(backend, std::span<const TopEntry>(entries));
  a.entry_object_boxes = BackendArray<Aabb>(backend, std::span<const Aabb>(object_boxes));
  a.boxes = BackendArray<Aabb>(backend, std::span<const Aabb>(boxes));
  std::vector<Vec3f> albedo = scene.albedo;
  albedo.resize(instances.size(), Vec3f{0.7f, 0.7f, 0.7f});
  a.albedo = BackendArray<Vec3f>(backend, std::span<const Vec3f>(albedo));
  a.spins = BackendArray<Spin>(backend, std::span<const Spin>(spins));
  build_top();
}

TwoLevelScene::~TwoLevelScene() = default;

Backend TwoLevelScene::backend() const { return arrays_->backend; }
TopLayout TwoLevelScene::top_layout() const { return arrays_->layout; }
int TwoLevelScene::instance_count() const { return arrays_->instance_count; }

TwoLevelView TwoLevelScene::view() const {
  const Arrays& a = *arrays_;
  TwoLevelView view{a.top.nodes(),    a.top.leaf_ids(),   a.top.node_count(),
                    a.entries.data(), a.instances.data(), a.bottom_views.data()};
  if (a.wide_top) view.top_wide = a.wide_top->view();
  return view;
}

ShadeView TwoLevelScene::shade_view() const {
  return {arrays_->mesh_views.data(), arrays_->albedo.data()};
}

void TwoLevelScene::build_top() {
  Arrays& a = *arrays_;
  a.top.build(a.boxes.data(), a.entry_count);
  if (a.wide_top)
    a.wide_top->run(a.top.nodes(), a.top.parents(), a.top.node_count(), nullptr,
                    a.top.leaf_ids());
}

void TwoLevelScene::move(double seconds) {
  Arrays& a = *arrays_;
  const int spinning = static_cast<int>(a.spins.size());
  if (spinning > 0) {
    for_each_index(
        a.backend, spinning,
        MoveInstances{a.spins.data(), seconds, a.instances.data(), a.to_world.data()});
    for_each_index(a.backend, a.entry_count,
                   BoxEntries{a.entries.data(), a.entry_object_boxes.data(), a.to_world.data(),
                              a.boxes.data()});
  }
  build_top();
}

int TwoLevelScene::entry_count() const { return arrays_->entry_count; }

double TwoLevelScene::bottom_bytes() const { return arrays_->bottom_bytes; }
double TwoLevelScene::top_bytes() const {
  const Arrays& a = *arrays_;
  return double(a.instance_count) * (sizeof(Instance) + sizeof(AffineD)) +
         double(a.entry_count) * (sizeof(TopEntry) + 2 * sizeof(Aabb) + sizeof(int)) +
         double(a.top.node_count()) * sizeof(BvhNode);
}

void trace_rays(const TwoLevelScene& scene, Query query, const RayF* rays, int count,
                InstanceHit* hits) {
  const Backend b = scene.backend();
  const TwoLevelView v = scene.view();
  with_top_layout(scene.top_layout(), [&](auto top) {
    if (query == Query::closest)
      for_each_ray(b, count, TraceRays<Query::closest, decltype(top)::value>{v, rays, hits});
    else
      for_each_ray(b, count, TraceRays<Query::any, decltype(top)::value>{v, rays, hits});
  });
}

void render_shaded(const TwoLevelScene& scene, const ch03::Camera<float>& camera, Extent extent,
                   Rgba8* pixels) {
  const PixelTiles tiles(extent.width, extent.height);
  with_top_layout(scene.top_layout(), [&](auto top) {
    for_each_ray(scene.backend(), static_cast<int>(tiles.count()),
                 ShadePixels<decltype(top)::value>{scene.view(), scene.shade_view(), camera,
                                                   tiles, pixels});
  });
}

} // namespace rt::ch13
