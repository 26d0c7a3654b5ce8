// Chapter 09: a collapsed tree stored as the traversal reads it: plain wide nodes, or
// compressed nodes with their boxes quantised outward. See collapse.h.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

#include "collapse.h"
#include "cpu_tree.h"
#include "rt/backend.h"
#include "rt/error.h"
#include "rt/launch.h"

namespace rt::ch09 {
namespace {

// The threads a layout is stored on: the collapse's.
int threads_of(const WideLayout& layout) {
  return layout.threads > 0 ? layout.threads : cpu_thread_count();
}

// The layout's triangles as nine columns (v0.x v0.y v0.z v1.x ... v2.z), padded so that a
// read of eight from any triangle stays inside; returns the column stride.
int write_columns(const WideLayout& layout, std::vector<float>& columns) {
  const int count = static_cast<int>(layout.triangles.size());
  const int stride = (count + 2 * 8 - 1) / 8 * 8;
  columns.assign(9 * static_cast<std::size_t>(stride), 0.0f);
  for_each_index_cpu(
      static_cast<std::size_t>(count),
      [&](std::size_t k) {
        const TriangleF& t = layout.triangles[k];
        const Vec3f v[3] = {t.v0, t.v1, t.v2};
        for (int c = 0; c < 9; ++c)
          columns[static_cast<std::size_t>(c) * stride + k] = v[c / 3][c % 3];
      },
      threads_of(layout), "triangles");
  return stride;
}

// The layout's stats, the time since `start` added to the build's, and the stored bytes (nodes
// and triangles) per triangle of the mesh: an sbvh tree's extra references are memory it pays
// for.
WideStats stored_stats(const WideLayout& layout, std::chrono::steady_clock::time_point start,
                       double stored_bytes) {
  WideStats stats = layout.stats;
  stats.build_ms +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
          .count();
  const double triangles = layout.stats.triangles > 0 ? double(layout.stats.triangles)
                                                      : double(layout.triangles.size());
  if (!layout.triangles.empty()) stats.bytes_per_triangle = stored_bytes / triangles;
  return stats;
}

// The triangle records and the stats, the time since `start` added to the build's.
template <class Node, class Triangles>
void finish(WideTree<Node, Triangles>& tree, const WideLayout& layout,
            std::chrono::steady_clock::time_point start) {
  tree.triangles.resize(layout.triangles.size() * Triangles::k_records);
  for_each_index_cpu(
      layout.triangles.size(),
      [&](std::size_t k) {
        Triangles::write(&tree.triangles[k * Triangles::k_records], layout.triangles[k],
                         layout.triangle_ids[k]);
      },
      threads_of(layout), "triangles");
  tree.column_stride = write_columns(layout, tree.columns);
  tree.stats = stored_stats(layout, start,
                            double(tree.nodes.size() * sizeof(Node) +
                                   tree.triangles.size() * sizeof(tree.triangles[0])));
}

// The non-empty slots of a node, in slot order: the positions its children take in a stored
// node (an interior child's slot travels in its meta byte).
int used_slots(const SlotNode& node, int (&slots)[k_slots]) {
  int count = 0;
  for (int s = 0; s < k_slots; ++s)
    if (node.meta[s] != 0) slots[count++] = s;
  return count;
}

} // namespace

template <int N, class Triangles>
WideTree<WideNode<N>, Triangles> pack_wide(const WideLayout& layout) {
  if (layout.width > N)
    throw InputError("a layout of width " + std::to_string(layout.width) +
                     " does not fit nodes of " + std::to_string(N));
  const auto start = std::chrono::steady_clock::now();
  WideTree<WideNode<N>, Triangles> tree;
  tree.nodes.resize(layout.nodes.size());
  // Each node from its own slot node, into its own place: the nodes are shared by the threads.
  for_each_index_cpu(
      layout.nodes.size(),
      [&](std::size_t i) {
        const SlotNode& from = layout.nodes[i];
        WideNode<N>& node = tree.nodes[i];
        int slots[k_slots];
        const int count = used_slots(from, slots);
        for (int c = 0; c < N; ++c) {
          set_child_box(node, c, c < count ? from.child_box[slots[c]] : Aabb{});
          node.meta[c] = c < count ? from.meta[slots[c]] : 0;
        }
        node.child_base = from.child_base;
        node.triangle_base = from.triangle_base;
        node.imask = from.imask;
      },
      threads_of(layout), "nodes");
  finish(tree, layout, start);
  return tree;
}

template Wide4Bvh pack_wide<4>(const WideLayout&);
template Wide8Bvh pack_wide<8>(const WideLayout&);
template Wide4PackedBvh pack_wide<4, PackedTriangles>(const WideLayout&);

// [listing:pack_cpu]
// The CPU's node from the same slot node: the boxes as pack_wide<8> stores them, and each
// child's word written out. An interior child in slot s is node child_base plus the interior
// children in the slots below s; a leaf's meta byte gives its triangles' bits. Each node's
// triangles are copied to blocks of their own, in the same order, so the bits still count
// from the node's (new) triangle_base. A first pass counts each node's blocks, a sum over the
// nodes in order places them, and a second pass writes every node and its blocks: each into
// its own place, so the threads share both passes and the tree is the same for any count.
CpuTree pack_cpu(const WideLayout& layout) {
  if (layout.width > k_slots)
    throw InputError("a layout of width " + std::to_string(layout.width) +
                     " does not fit the CPU's nodes of 8");
  const auto start = std::chrono::steady_clock::now();
  const int threads = threads_of(layout);
  const std::size_t node_count = layout.nodes.size();
  // A node's triangles: triangle_base .. + 31 - countl_zero(its leaves' bits).
  const auto leaf_bits = [](const SlotNode& from) {
    unsigned all_leaves = 0;
    for (int s = 0; s < k_slots; ++s)
      if (from.meta[s] != 0 && !is_interior_meta(from.meta[s]))
        all_leaves |= meta_bits(from.meta[s], 0);
    return all_leaves;
  };
  std::vector<int> block_start(node_count + 1, 0); // each node's first block
  for_each_index_cpu(
      node_count,
      [&](std::size_t i) {
        const int triangles = 32 - std::countl_zero(leaf_bits(layout.nodes[i]));
        block_start[i + 1] = (triangles + k_block_triangles - 1) / k_block_triangles;
      },
      threads, "nodes");
  for (std::size_t i = 0; i < node_count; ++i) block_start[i + 1] += block_start[i];
  CpuTree tree;
  tree.nodes.resize(node_count);
  tree.columns.resize(std::size_t(block_start[node_count]) * k_block_floats, 0.0f);
  tree.ids.resize(std::size_t(block_start[node_count]) * k_block_triangles, -1);
  for_each_index_cpu(
      node_count,
      [&](std::size_t i) {
        const SlotNode& from = layout.nodes[i];
        CpuNode& node = tree.nodes[i];
        int slots[k_slots];
        const int count = used_slots(from, slots);
        for (int c = 0; c < k_slots; ++c) {
          set_child_box(node, c, c < count ? from.child_box[slots[c]] : Aabb{});
          node.child[c] = cpu_leaf_child(0); // empty: a leaf of no triangles
          if (c >= count) continue;
          const std::uint8_t meta = from.meta[slots[c]];
          const unsigned below = from.imask & ((1u << slots[c]) - 1u);
          node.child[c] = is_interior_meta(meta) ? from.child_base + std::popcount(below)
                                                 : cpu_leaf_child(meta_bits(meta, 0));
        }
        const int first_slot = block_start[i] * k_block_triangles;
        node.triangle_base = first_slot;
        const int triangles = 32 - std::countl_zero(leaf_bits(from));
        for (int k = 0; k < triangles; ++k) {
          const int slot = first_slot + k, from_k = from.triangle_base + k;
          const TriangleF& t = layout.triangles[from_k];
          const Vec3f v[3] = {t.v0, t.v1, t.v2};
          float* block = &tree.columns[std::size_t(slot / k_block_triangles) * k_block_floats];
          for (int c = 0; c < 9; ++c)
            block[c * k_block_triangles + slot % k_block_triangles] = v[c / 3][c % 3];
          tree.ids[slot] = layout.triangle_ids[from_k];
        }
      },
      threads, "nodes");
  tree.stats =
      stored_stats(layout, start,
                   double(tree.nodes.size() * sizeof(CpuNode) +
                          tree.columns.size() * sizeof(float) + tree.ids.size() * sizeof(int)));
  return tree;
}
// [/listing:pack_cpu]

// [listing:quantise]
// Rounding outward, and why it holds. dequantise(q) = fl(q * step + origin), and q * step is
// exact, so dequantise(q) is the exact value q * step + origin rounded to the nearest float.
// Rounding to nearest is monotone: x <= y implies fl(x) <= fl(y). Hence dequantise is
// non-decreasing in q, and a binary search finds the largest q whose plane is <= lo and the
// smallest whose plane is >= hi. Those q exist: dequantise(0) = origin = the node box's lo <=
// every child's lo, and the grid is chosen so that dequantise(255) >= the node box's hi >=
// every child's hi. The planes are computed by the very function the traversal calls, so the
// box the traversal tests contains the child's exact box: no quantisation error can make a ray
// miss a child it touches. The search is exact even where step is below a float's spacing at
// origin (far from the origin, tiny boxes), where a plane moves only every few steps.
AxisGrid choose_grid(float lo, float hi) {
  if (!(lo <= hi)) throw Error("choose_grid: the box is empty");
  const double extent = double(hi) - double(lo);
  int e = k_min_grid_exponent;
  if (extent > 0.0) { // from just below 2^e = extent / 255, up to the first that reaches hi
    int estimate = 0;
    std::frexp(extent / 255.0, &estimate);
    e = std::max(e, estimate - 2);
  }
  for (;; ++e) {
    if (e > k_max_grid_exponent)
      throw InputError("a node spans " + std::to_string(lo) + " to " + std::to_string(hi) +
                       ": wider than the compressed node's grid (255 * 2^" +
                       std::to_string(k_max_grid_exponent) + ")");
    const AxisGrid grid{lo, static_cast<std::uint8_t>(e + 127)};
    if (dequantise(255, grid.step(), lo) >= hi) return grid;
  }
}

std::uint8_t quantise_lo(float lo, const AxisGrid& grid) {
  const float step = grid.step();
  if (!(dequantise(0, step, grid.origin) <= lo)) throw Error("quantise_lo: below the grid");
  int below = 0, above = 256; // dequantise(below) <= lo; above: past the largest such q
  while (above - below > 1) {
    const int mid = (below + above) / 2;
    (dequantise(static_cast<std::uint8_t>(mid), step, grid.origin) <= lo ? below : above) = mid;
  }
  return static_cast<std::uint8_t>(below);
}

std::uint8_t quantise_hi(float hi, const AxisGrid& grid) {
  const float step = grid.step();
  if (!(dequantise(255, step, grid.origin) >= hi)) throw Error("quantise_hi: above the grid");
  int below = -1, above = 255; // dequantise(above) >= hi; below: before the smallest such q
  while (above - below > 1) {
    const int mid = (below + above) / 2;
    (dequantise(static_cast<std::uint8_t>(mid), step, grid.origin) >= hi ? above : below) = mid;
  }
  return static_cast<std::uint8_t>(above);
}
// [/listing:quantise]

CompressedBvh compress(const WideLayout& layout) {
  if (layout.width > k_slots)
    throw InputError("a compressed node holds 8 children, not " + std::to_string(layout.width));
  const auto start = std::chrono::steady_clock::now();
  CompressedBvh tree;
  tree.nodes.resize(layout.nodes.size());
  // A node too wide for its grid throws: the first such node in order is the one named.
  for_each_index_cpu(
      layout.nodes.size(),
      [&](std::size_t i) {
        const SlotNode& from = layout.nodes[i];
        CompressedNode& node = tree.nodes[i];
        const AxisGrid grid[3] = {choose_grid(from.box.lo.x, from.box.hi.x),
                                  choose_grid(from.box.lo.y, from.box.hi.y),
                                  choose_grid(from.box.lo.z, from.box.hi.z)};
        for (int a = 0; a < 3; ++a) {
          node.origin[a] = grid[a].origin;
          node.exponent[a] = grid[a].exponent;
        }
        int slots[k_slots];
        const int count = used_slots(from, slots);
        for (int c = 0; c < count; ++c) { // empty children keep q = 0 and meta 0: no bits
          const Aabb& box = from.child_box[slots[c]];
          node.meta[c] = from.meta[slots[c]];
          node.q_lo_x[c] = quantise_lo(box.lo.x, grid[0]);
          node.q_lo_y[c] = quantise_lo(box.lo.y, grid[1]);
          node.q_lo_z[c] = quantise_lo(box.lo.z, grid[2]);
          node.q_hi_x[c] = quantise_hi(box.hi.x, grid[0]);
          node.q_hi_y[c] = quantise_hi(box.hi.y, grid[1]);
          node.q_hi_z[c] = quantise_hi(box.hi.z, grid[2]);
        }
        node.child_base = from.child_base;
        node.triangle_base = from.triangle_base;
        node.imask = from.imask;
      },
      threads_of(layout), "parts");
  finish(tree, layout, start);
  return tree;
}

template <int N> Aabb child_box_of(const WideNode<N>& node, int c) {
  return {{node.lo_x[c], node.lo_y[c], node.lo_z[c]},
          {node.hi_x[c], node.hi_y[c], node.hi_z[c]}};
}
template Aabb child_box_of<4>(const WideNode<4>&, int);
template Aabb child_box_of<8>(const WideNode<8>&, int);

Aabb child_box_of(const CompressedNode& node, int c) {
  const float sx = grid_step(node.exponent[0]), sy = grid_step(node.exponent[1]),
              sz = grid_step(node.exponent[2]);
  return {{dequantise(node.q_lo_x[c], sx, node.origin[0]),
           dequantise(node.q_lo_y[c], sy, node.origin[1]),
           dequantise(node.q_lo_z[c], sz, node.origin[2])},
          {dequantise(node.q_hi_x[c], sx, node.origin[0]),
           dequantise(node.q_hi_y[c], sy, node.origin[1]),
           dequantise(node.q_hi_z[c], sz, node.origin[2])}};
}

} // namespace rt::ch09
