// Chapter 13: scenes of instances on the host. See instance_scene.h.
#include "instance_scene.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

#include "bvh_build.h"
#include "collapse.h"
#include "rt/error.h"

namespace rt::ch13 {

std::vector<Instance> make_instances(const InstanceScene& scene) {
  if (static_cast<long long>(scene.placements.size()) > k_max_instances)
    throw InputError(std::to_string(scene.placements.size()) + " instances: at most " +
                     std::to_string(k_max_instances) + " are supported");
  std::vector<Instance> out;
  out.reserve(scene.placements.size());
  for (std::size_t k = 0; k < scene.placements.size(); ++k) {
    const Placement& p = scene.placements[k];
    const std::string what = "instance " + std::to_string(k);
    if (p.mesh < 0 || static_cast<std::size_t>(p.mesh) >= scene.meshes.size())
      throw InputError(what + ": mesh " + std::to_string(p.mesh) + " does not exist (" +
                       std::to_string(scene.meshes.size()) + " meshes)");
    out.push_back(make_instance(p.to_world, p.mesh, p.mask, what));
  }
  return out;
}

namespace {

// The subtrees `levels` below the root of a 4-wide tree, as instance_scene.h says: a node whose
// slots are all subtrees is replaced by them, any other stays.
void open_tree(const ch09::Wide4PackedBvh& tree, const Aabb& root_box, int levels,
               std::vector<int>& nodes, std::vector<Aabb>& boxes) {
  nodes = {0};
  boxes = {root_box};
  for (int level = 0; level < levels; ++level) {
    std::vector<int> next_nodes;
    std::vector<Aabb> next_boxes;
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const ch09::WideNode<4>& node = tree.nodes[nodes[k]];
      // A child's place in the node is not its slot: an interior child's meta byte names its
      // (octant) slot, and it is node child_base + the interior children in slots below it,
      // as the walk finds it (wide_traverse.h).
      bool all_subtrees = true;
      int children = 0;
      for (int c = 0; c < 4; ++c) {
        if (node.meta[c] == 0) continue; // an empty place
        if (!ch09::is_interior_meta(node.meta[c])) all_subtrees = false;
        ++children;
      }
      if (!all_subtrees || children < 2) {
        next_nodes.push_back(nodes[k]);
        next_boxes.push_back(boxes[k]);
        continue;
      }
      for (int c = 0; c < 4; ++c) {
        if (node.meta[c] == 0) continue;
        const int slot = (node.meta[c] & 31) - ch09::k_triangle_bits;
        next_nodes.push_back(node.child_base +
                             std::popcount(unsigned(node.imask) & ((1u << slot) - 1u)));
        next_boxes.push_back(ch09::child_box_of(node, c));
      }
    }
    nodes = std::move(next_nodes);
    boxes = std::move(next_boxes);
  }
}

} // namespace

BottomLevel build_bottom_level(const std::vector<ch04::Mesh>& meshes, int open_levels) {
  if (open_levels < 0 || open_levels > k_max_open_levels)
    throw InputError("opening instances " + std::to_string(open_levels) +
                     " levels: it takes 0 to " + std::to_string(k_max_open_levels));
  const auto start = std::chrono::steady_clock::now();
  BottomLevel bottom;
  for (const ch04::Mesh& mesh : meshes) {
    const ch07::Bvh binary =
        ch07::build_bvh(mesh, ch09::binary_options(ch09::Collapse::sah, {}));
    bottom.object_boxes.push_back(binary.bounds);
    bottom.trees.push_back(ch09::pack_wide<4, ch09::PackedTriangles>(
        ch09::collapse(binary, 4, ch09::Collapse::sah)));
    const ch09::Wide4PackedBvh& tree = bottom.trees.back();
    const int levels =
        static_cast<long long>(mesh.triangles.size()) >= k_open_min_triangles ? open_levels : 0;
    bottom.open_nodes.emplace_back();
    bottom.open_boxes.emplace_back();
    open_tree(tree, binary.bounds, tree.nodes.empty() ? 0 : levels, bottom.open_nodes.back(),
              bottom.open_boxes.back());
    bottom.bytes += double(tree.nodes.size() * sizeof(tree.nodes[0]) +
                           tree.triangles.size() * sizeof(tree.triangles[0]));
  }
  bottom.build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
          .count();
  return bottom;
}

Flattened flatten(const InstanceScene& scene) {
  Flattened out;
  long long total = 0;
  for (const Placement& p : scene.placements) {
    out.first_triangle.push_back(total);
    total += static_cast<long long>(scene.meshes.at(p.mesh).triangles.size());
  }
  out.first_triangle.push_back(total);
  if (total > ch07::k_max_bvh_triangles)
    throw InputError("flattened, the scene has " + std::to_string(total) +
                     " triangles: more than one tree holds (" +
                     std::to_string(ch07::k_max_bvh_triangles) + ")");
  for (const Placement& p : scene.placements) {
    const ch04::Mesh& mesh = scene.meshes[p.mesh];
    const int base = static_cast<int>(out.mesh.vertices.size());
    for (const Vec3f& v : mesh.vertices)
      out.mesh.vertices.push_back(p.to_world.point(v.as<double>()).as<float>());
    for (const ch04::IndexedTriangle& t : mesh.triangles)
      out.mesh.triangles.push_back({base + t.v0, base + t.v1, base + t.v2});
  }
  return out;
}

Forest make_forest(const ch04::Mesh& tree, int count, unsigned seed, double speed) {
  if (count < 1 || count > k_max_instances - 1)
    throw InputError("a forest of " + std::to_string(count) + " trees: it takes 1 to " +
                     std::to_string(k_max_instances - 1));
  if (tree.triangles.empty()) throw InputError("a forest needs a tree with triangles");
  // The tree's footprint sets the grid's spacing, and its base sits on the ground.
  Aabb box;
  for (const Vec3f& v : tree.vertices) box.grow(v);
  const double width = std::max(box.hi.x - box.lo.x, box.hi.z - box.lo.z);
  const double spacing = 1.3 * width;
  const Vec3d centre{0.5 * (box.lo.x + box.hi.x), double(box.lo.y),
                     0.5 * (box.lo.z + box.hi.z)};
  const int side = static_cast<int>(std::ceil(std::sqrt(double(count))));
  const double extent = side * spacing;

  Forest forest;
  InstanceScene& scene = forest.scene;
  scene.meshes.push_back(tree);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < count; ++k) {
    Spin s;
    s.scale = 0.8 + 0.4 * unit(random);
    s.yaw = 2.0 * std::numbers::pi * unit(random);
    s.speed = speed * (unit(random) < 0.5 ? -1.0 : 1.0) * (0.5 + unit(random));
    const double x = (k % side + 0.5 + 0.2 * (unit(random) - 0.5)) * spacing - 0.5 * extent;
    const double z = (k / side + 0.5 + 0.2 * (unit(random) - 0.5)) * spacing - 0.5 * extent;
    // The mesh's own base centre goes to (x, 0, z): turn and scale about it.
    const Vec3d offset =
        spin_transform({{0, 0, 0}, s.yaw, 0.0, s.scale}, 0.0).direction(centre);
    s.position = Vec3d{x, 0.0, z} - offset;
    forest.spins.push_back(s);
    scene.placements.push_back({spin_transform(s, 0.0), 0});
    const double hue = unit(random);
    scene.albedo.push_back(
        Vec3d{0.25 + 0.35 * hue, 0.45 + 0.25 * unit(random), 0.2 + 0.3 * (1.0 - hue)}
            .as<float>());
  }
  // The ground: a square of two triangles under the whole grid.
  ch04::Mesh ground;
  const float g = static_cast<float>(0.6 * extent + spacing);
  ground.vertices = {{-g, 0.0f, -g}, {g, 0.0f, -g}, {g, 0.0f, g}, {-g, 0.0f, g}};
  ground.triangles = {{0, 2, 1}, {0, 3, 2}};
  scene.meshes.push_back(ground);
  scene.placements.push_back({AffineD{}, 1});
  scene.albedo.push_back({0.55f, 0.5f, 0.45f});

  // The camera stands over one corner, three trees high, and looks along the diagonal about
  // 20 degrees down: rows of trees from the front of the picture to the horizon.
  ch03::CameraSpec camera;
  const double height = box.hi.y - box.lo.y;
  const double eye_height = 3.0 * height,
               ahead = eye_height / std::tan(20.0 * std::numbers::pi / 180.0);
  const double corner = -0.5 * extent;
  camera.eye = {corner, eye_height, corner};
  camera.target = {corner + ahead / std::sqrt(2.0), 0.0, corner + ahead / std::sqrt(2.0)};
  camera.up = {0.0, 1.0, 0.0};
  camera.fov_degrees = 50.0;
  scene.camera = camera;
  scene.description = "a forest of " + std::to_string(count) + " trees of " +
                      std::to_string(tree.triangles.size()) + " triangles";
  return forest;
}

} // namespace rt::ch13
