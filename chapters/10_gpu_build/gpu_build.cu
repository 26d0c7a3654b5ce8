// Chapter 10: the LBVH and the refit, pass by pass. See gpu_build.h. Every pass is a functor
// with an RT_HD call operator run by for_each_index, on the GPU or on CPU threads; the sort is
// CUB's radix sort on the GPU and std::stable_sort on the CPU, both stable, so both backends
// give the same tree bit for bit.
#include "gpu_build.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <utility>

#include "build_passes.cuh"
#include "bvh_build.h"
#include "karras.h"
#include "model_render.h"
#include "rt/error.h"

namespace rt::ch10 {

const char* to_string(CodeWidth width) {
  return width == CodeWidth::bits30 ? "30-bit" : "63-bit";
}

namespace {

using namespace passes;

// Pass 3: interior node i of the Karras tree, and its children's parent links.
template <class Code> struct BuildHierarchy {
  const Code* codes;
  int n;
  KarrasNode* nodes;
  int* parents; // of the interior nodes: 2 * parent + child slot; -1 for the root
  RT_HD void operator()(int i) const {
    const KarrasNode node = karras_node(codes, n, i);
    nodes[i] = node;
    for (int c = 0; c < 2; ++c)
      if (!node.is_leaf[c]) parents[node.child[c]] = 2 * i + c;
    if (i == 0) parents[0] = -1;
  }
};

// [listing:depth_first_index]
// Pass 4: where interior node i goes in chapter 07's depth-first array. Before a node, a
// depth-first walk visits its ancestors and the whole subtrees to the left of its range. Those
// subtrees cover leaves 0 .. first-1; k subtrees covering `first` leaves hold first - k
// interior nodes, and k is the number of ancestors the node lies right of. So the index is
// first + (the number of ancestors it lies left of), counted on the way up. The walk stops at
// chapter 07's depth bound: a node deeper than that marks the tree too deep for the traversal
// stack, and the tree is not laid out.
struct PlaceDepthFirst {
  const KarrasNode* nodes;
  const int* parents;
  int* index;
  int* too_deep;
  RT_HD void operator()(int i) const {
    int left_turns = 0, depth = 0;
    for (int x = i; x != 0; x = parents[x] >> 1) {
      if (++depth > ch07::k_max_bvh_depth - 1) {
        mark(too_deep);
        return;
      }
      left_turns += (parents[x] & 1) == 0;
    }
    index[i] = nodes[i].first + left_turns;
  }
};
// [/listing:depth_first_index]

// Pass 5: the node in chapter 07's layout, boxes still to come; a leaf child names its one
// triangle, which sits at the leaf's own position in the sorted order.
struct WriteLayout {
  const KarrasNode* nodes;
  const int* index;
  BvhNode* out;
  int* out_parents;
  RT_HD void operator()(int i) const {
    const KarrasNode& node = nodes[i];
    const int at = index[i];
    BvhNode written;
    for (int c = 0; c < 2; ++c) {
      written.first[c] = node.is_leaf[c] ? node.child[c] : index[node.child[c]];
      written.count[c] = node.is_leaf[c] ? 1 : 0;
      if (!node.is_leaf[c]) out_parents[written.first[c]] = 2 * at + c;
    }
    out[at] = written;
    if (i == 0) out_parents[0] = -1;
  }
};

// The tree of a single box: the root of chapter 07's one-leaf tree (single_leaf_root), whose
// leaf slot 0 holds box 0.
struct WriteSingleLeaf {
  const Aabb* boxes;
  BvhNode* nodes;
  int* leaf_ids;
  RT_HD void operator()(int) const {
    nodes[0] = single_leaf_root(boxes[0]);
    leaf_ids[0] = 0;
  }
};

// Passes 3 to 5 over n >= 2 sorted codes, whatever they are the codes of: Karras's
// hierarchy, each interior node's place in chapter 07's depth-first array, and the nodes
// written there with their parent links, boxes still to come. The arrays hold up to
// `capacity` codes' nodes, made once.
template <class Code> struct HierarchyPasses {
  BackendArray<int> parents, index, too_deep;
  BackendArray<KarrasNode> karras;

  HierarchyPasses(Backend backend, int capacity)
      : parents(backend, std::max(capacity - 1, 0)), index(backend, std::max(capacity - 1, 0)),
        too_deep(backend, 1), karras(backend, std::max(capacity - 1, 0)), backend_(backend) {}

  // The n - 1 nodes into `nodes`, their parents into `node_parents`. False when the tree is
  // deeper than the traversal stack allows; only looked at (a wait on the GPU) with
  // check_depth, which 30-bit codes do not need (see the depth proof below).
  bool lay_out(const Code* sorted_codes, int n, BvhNode* nodes, int* node_parents,
               bool check_depth) {
    if (check_depth) too_deep.fill_bytes(0);
    for_each_index(backend_, n - 1,
                   BuildHierarchy<Code>{sorted_codes, n, karras.data(), parents.data()});
    for_each_index(
        backend_, n - 1,
        PlaceDepthFirst{karras.data(), parents.data(), index.data(), too_deep.data()});
    if (check_depth && too_deep.to_host()[0] != 0) return false;
    for_each_index(backend_, n - 1,
                   WriteLayout{karras.data(), index.data(), nodes, node_parents});
    return true;
  }

private:
  Backend backend_;
};

// The LBVH's arrays for a mesh where the backend reads it, made once; build() runs the passes
// into `tree`, as often as the vertices move.
template <class Code> struct LbvhPasses {
  int n;
  MortonOrder<Code> order;
  HierarchyPasses<Code> hierarchy;
  TreeArrays tree;

  LbvhPasses(Backend backend, MeshView mesh)
      : n(mesh.triangle_count), order(backend, mesh), hierarchy(backend, n),
        tree(backend, n - 1, n), backend_(backend) {}

  // False when check_depth and the tree is deeper than the traversal stack allows.
  bool build(bool check_depth) {
    order.sort();
    if (!hierarchy.lay_out(order.sorted_codes.data(), n, tree.nodes.data(), tree.parents.data(),
                           check_depth))
      return false;
    for_each_index(backend_, n,
                   GatherTriangles{order.mesh, order.sorted_ids.data(), tree.triangles.data()});
    box_bottom_up(backend_, tree.nodes, tree.parents, tree.triangles, tree.arrivals);
    // The sorted numbers become the tree's ids; the next sort writes into the old ids.
    std::swap(tree.triangle_ids, order.sorted_ids);
    return true;
  }

private:
  Backend backend_;
};

// The whole LBVH from codes of type Code; nothing when the tree is deeper than the traversal
// stack allows.
template <class Code>
std::optional<GpuBuild> build_from_codes(Backend backend, const ch04::Mesh& mesh) {
  MeshArrays d_mesh(backend, mesh);
  LbvhPasses<Code> lbvh(backend, d_mesh.view());
  BackendStopwatch clock(backend); // build time: events around the kernels, or wall time
  if (!lbvh.build(true)) return std::nullopt;
  GpuBuild build;
  build.build_ms = clock.milliseconds();
  build.codes = sizeof(Code) == 4 ? CodeWidth::bits30 : CodeWidth::bits63;
  build.bvh.nodes = lbvh.tree.nodes.to_host();
  build.bvh.triangles = lbvh.tree.triangles.to_host();
  build.bvh.triangle_ids = lbvh.tree.triangle_ids.to_host();
  build.bvh.bounds = root_bounds(build.bvh);
  return build;
}

} // namespace

// [listing:depth_proof]
// Why a tree of 30-bit codes always fits chapter 07's stack. Karras's tree is a binary radix
// tree over the keys (code, index): an interior node's children share strictly longer
// prefixes than the node itself, so the prefix length delta grows by at least one per level
// down. The deepest interior node of a radix tree therefore sits at most (the number of values
// delta can take for an interior node) - 1 below the root. For 30-bit codes in a 32-bit word,
// delta of two different codes is 2..31 (the top two bits are always zero): 30 values. Two
// equal codes give 32 + the common prefix of two leaf numbers below n <= 2^28, which is 4..31:
// 28 values. 58 values in all: no interior node deeper than 57 < k_max_bvh_depth - 1 = 63.
// The 63-bit codes give 63 + 28 = 91 possible values, so their trees can be too deep (points
// spaced by powers of two along the axes, then many triangles at one point, make one): the
// walk that places the nodes sees it, and the tree is built again from 30-bit codes.
static_assert(30 + 28 - 1 <= ch07::k_max_bvh_depth - 1);
static_assert(ch07::k_max_bvh_triangles == 1LL << 28);
// [/listing:depth_proof]

GpuBuild build_lbvh(Backend backend, const ch04::Mesh& mesh, CodeWidth codes) {
  ch07::check_build_input(mesh);
  const int n = static_cast<int>(mesh.triangles.size());
  if (backend == Backend::gpu)
    ch05::check_device_memory(static_cast<std::size_t>(n) * device_bytes_per_triangle(),
                              "the LBVH of " + std::to_string(n) + " triangles");
  GpuBuild build;
  if (n == 1) build.bvh = single_leaf_tree(mesh);
  if (n >= 2) {
    std::optional<GpuBuild> built = codes == CodeWidth::bits63
                                        ? build_from_codes<std::uint64_t>(backend, mesh)
                                        : build_from_codes<std::uint32_t>(backend, mesh);
    if (!built) {
      built = build_from_codes<std::uint32_t>(backend, mesh);
      if (!built) throw Error("an LBVH of 30-bit codes came out too deep: see the proof");
      built->note = "63-bit codes gave a tree deeper than the traversal stack; built from "
                    "30-bit codes";
    }
    build = std::move(*built);
  }
  build.bvh.options.method = ch07::SplitMethod::median; // a spatial median: Morton's bits
  build.bvh.options.max_leaf_size = 1;
  build.bvh.stats.build_ms = build.build_ms;
  fill_stats(build.bvh);
  return build;
}

struct LbvhOnBackend::Passes : LbvhPasses<std::uint32_t> {
  using LbvhPasses::LbvhPasses;
};

LbvhOnBackend::LbvhOnBackend(Backend backend, ch04::MeshView mesh) {
  if (mesh.triangle_count < 2) throw InputError("an LBVH on the backend needs two triangles");
  passes_ = std::make_unique<Passes>(backend, mesh);
}
LbvhOnBackend::~LbvhOnBackend() = default;
void LbvhOnBackend::build() { passes_->build(false); }
TreeArrays& LbvhOnBackend::tree() { return passes_->tree; }

// [listing:lbvh_over_boxes]
// The LBVH over boxes: the passes of the mesh's LBVH with CentreBoxes for BoxTriangles, no
// triangle copies, and leaves boxed from the caller's boxes through the sorted numbers.
struct LbvhOverBoxes::Passes {
  Backend backend;
  int capacity;
  int count = 0; // the boxes of the last build
  MortonOrder<std::uint32_t> order;
  HierarchyPasses<std::uint32_t> hierarchy;
  BackendArray<BvhNode> nodes;
  BackendArray<int> parents;
  BackendArray<unsigned> arrivals;

  Passes(Backend b, int c)
      : backend(b), capacity(c), order(b, c), hierarchy(b, c), nodes(b, std::max(c - 1, 1)),
        parents(b, std::max(c - 1, 1)), arrivals(b, std::max(c - 1, 1)) {}

  void build(const Aabb* boxes, int n) {
    count = n;
    if (n == 1) {
      for_each_index(backend, 1, WriteSingleLeaf{boxes, nodes.data(), order.sorted_ids.data()});
    } else if (n >= 2) {
      order.sort_boxes(boxes, n);
      hierarchy.lay_out(order.sorted_codes.data(), n, nodes.data(), parents.data(), false);
      box_bottom_up(backend, n - 1, nodes, parents, arrivals,
                    BoxLeaves{boxes, order.sorted_ids.data()});
    }
  }
};
// [/listing:lbvh_over_boxes]

LbvhOverBoxes::LbvhOverBoxes(Backend backend, int capacity) {
  if (backend != Backend::cpu && backend != Backend::gpu)
    throw UsageError("an LBVH over boxes needs a resolved backend");
  if (capacity < 0 || capacity > ch07::k_max_bvh_triangles)
    throw UsageError("an LBVH over boxes holds 0 to " +
                     std::to_string(ch07::k_max_bvh_triangles) + " boxes, not " +
                     std::to_string(capacity));
  if (backend == Backend::gpu)
    ch05::check_device_memory(static_cast<std::size_t>(capacity) * device_bytes_per_triangle(),
                              "the LBVH over " + std::to_string(capacity) + " boxes");
  passes_ = std::make_unique<Passes>(backend, capacity);
}
LbvhOverBoxes::~LbvhOverBoxes() = default;
LbvhOverBoxes::LbvhOverBoxes(LbvhOverBoxes&&) noexcept = default;
LbvhOverBoxes& LbvhOverBoxes::operator=(LbvhOverBoxes&&) noexcept = default;

void LbvhOverBoxes::build(const Aabb* boxes, int count) {
  if (count < 0 || count > passes_->capacity)
    throw UsageError("an LBVH over boxes made for " + std::to_string(passes_->capacity) +
                     " boxes was given " + std::to_string(count));
  passes_->build(boxes, count);
}
const BvhNode* LbvhOverBoxes::nodes() const { return passes_->nodes.data(); }
const int* LbvhOverBoxes::leaf_ids() const { return passes_->order.sorted_ids.data(); }
const int* LbvhOverBoxes::parents() const { return passes_->parents.data(); }
int LbvhOverBoxes::count() const { return passes_->count; }
int LbvhOverBoxes::node_count() const {
  return passes_->count <= 1 ? passes_->count : passes_->count - 1;
}
int LbvhOverBoxes::capacity() const { return passes_->capacity; }

BoxTree LbvhOverBoxes::to_host() const {
  BoxTree tree;
  tree.nodes = passes_->nodes.to_host();
  tree.nodes.resize(node_count());
  tree.leaf_ids = passes_->order.sorted_ids.to_host();
  tree.leaf_ids.resize(count());
  return tree;
}

BoxTree build_lbvh_over_boxes(Backend backend, std::span<const Aabb> boxes) {
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Aabb& b = boxes[i];
    const bool finite = std::isfinite(b.lo.x) && std::isfinite(b.lo.y) &&
                        std::isfinite(b.lo.z) && std::isfinite(b.hi.x) &&
                        std::isfinite(b.hi.y) && std::isfinite(b.hi.z);
    if (!finite || b.empty())
      throw InputError("LBVH over boxes: box " + std::to_string(i) +
                       (finite ? " is empty (lo above hi)" : " is not finite"));
  }
  if (boxes.size() > static_cast<std::size_t>(ch07::k_max_bvh_triangles))
    throw InputError("LBVH over boxes: " + std::to_string(boxes.size()) +
                     " boxes, more than the " + std::to_string(ch07::k_max_bvh_triangles) +
                     " the depth proof allows");
  const int count = static_cast<int>(boxes.size());
  const BackendArray<Aabb> d_boxes(backend, boxes);
  LbvhOverBoxes lbvh(backend, count);
  lbvh.build(d_boxes.data(), count);
  return lbvh.to_host();
}

void refit_tree(Backend backend, TreeArrays& tree, ch04::MeshView mesh) {
  for_each_index(backend, mesh.triangle_count,
                 GatherTriangles{mesh, tree.triangle_ids.data(), tree.triangles.data()});
  box_bottom_up(backend, tree.nodes, tree.parents, tree.triangles, tree.arrivals);
}

double refit_bvh(Backend backend, ch07::Bvh& bvh, const ch04::Mesh& mesh) {
  ch07::check_build_input(mesh);
  if (mesh.triangles.size() != bvh.triangle_ids.size())
    throw InputError("refit: the mesh has " + std::to_string(mesh.triangles.size()) +
                     " triangles, the tree " + std::to_string(bvh.triangle_ids.size()));
  const int count = static_cast<int>(bvh.nodes.size());
  if (count == 0) return 0.0;
  MeshArrays d_mesh(backend, mesh);
  BackendArray<BvhNode> nodes(backend, std::span<const BvhNode>(bvh.nodes));
  BackendArray<int> ids(backend, std::span<const int>(bvh.triangle_ids)),
      parents(backend, count);
  BackendArray<TriangleF> triangles(backend, mesh.triangles.size());
  BackendArray<unsigned> arrivals(backend, count);
  BackendStopwatch clock(backend); // build time: events around the kernels, or wall time
  for_each_index(backend, static_cast<int>(mesh.triangles.size()),
                 GatherTriangles{d_mesh.view(), ids.data(), triangles.data()});
  const bool single_leaf = count == 1 && bvh.nodes[0].count[1] == 0;
  if (!single_leaf) {
    for_each_index(backend, count, LinkParents{nodes.data(), parents.data()});
    box_bottom_up(backend, nodes, parents, triangles, arrivals);
  }
  const double ms = clock.milliseconds();
  bvh.triangles = triangles.to_host();
  bvh.nodes = nodes.to_host();
  if (single_leaf) {
    // One leaf under the root: its box is the whole mesh's (the other child stays empty).
    Aabb all;
    for (const TriangleF& t : bvh.triangles) all.grow(ch07::bounds_of(t));
    bvh.nodes[0].box[0] = all;
  }
  bvh.bounds = root_bounds(bvh);
  fill_stats(bvh);
  return ms;
}

void fill_stats(ch07::Bvh& bvh) {
  ch07::BuildStats stats;
  stats.build_ms = bvh.stats.build_ms;
  stats.leaf_sizes.assign(bvh.options.max_leaf_size + 1, 0);
  std::vector<std::pair<int, int>> stack; // node, depth
  if (!bvh.nodes.empty()) stack.push_back({0, 0});
  while (!stack.empty()) {
    const auto [i, depth] = stack.back();
    stack.pop_back();
    ++stats.nodes;
    stats.depth = std::max(stats.depth, depth);
    for (int c = 0; c < 2; ++c) {
      const BvhNode& node = bvh.nodes[i];
      if (node.is_leaf(c)) {
        ++stats.leaves;
        if (node.count[c] < static_cast<int>(stats.leaf_sizes.size()))
          ++stats.leaf_sizes[node.count[c]];
      } else if (node.first[c] > i) {
        stack.push_back({node.first[c], depth + 1});
      }
    }
  }
  stats.sah_cost = ch07::sah_cost(bvh);
  const auto n = static_cast<double>(bvh.triangle_ids.size());
  if (n > 0)
    stats.bytes_per_triangle = (static_cast<double>(bvh.nodes.size() * sizeof(BvhNode)) +
                                n * static_cast<double>(sizeof(TriangleF) + sizeof(int))) /
                               n;
  bvh.stats = std::move(stats);
}

} // namespace rt::ch10
