// Chapter 10: the parallel collapse to Wide4PackedBvh, pass by pass. See wide_collapse.h.
// Every wide node is numbered by exclusive scans over the binary nodes in index order (CUB's on
// the GPU, std::exclusive_scan on the CPU), not by atomics, so both backends give the same
// tree bit for bit.
#include "wide_collapse.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>

#include <cub/device/device_scan.cuh>

#include "build_passes.cuh"
#include "collapse.h"
#include "octant_slots.h"
#include "refit.h" // second_arrival, load_published
#include "rt/error.h"

namespace rt::ch10 {
namespace {

using namespace passes;
using ch09::WideNode;

constexpr int k_width = 4;

// What the passes read and write, one entry per binary node unless said otherwise.
struct CollapseView {
  const BvhNode* nodes;
  const int* parents;
  const TriangleF* triangles; // in the binary tree's leaf order; null: ids alone (boxes)
  const int* triangle_ids;
  int leaf_size;    // the most triangles a wide leaf takes: 1 to 3
  int* range_first; // depth rule: the node's triangles are range_first .. range_end - 1
  int* range_end;
  int* is_wide;
  int* interior_counts; // of a wide node: its interior children, and its leaves' triangles
  int* leaf_counts;
  const int* interior_offsets; // exclusive scans of the two counts
  const int* triangle_offsets;
  int* wide_index;   // of a wide node: its number in the wide tree
  WideOrder* orders; // of a wide node: its children, as CountChildren found them
  WideNode<k_width>* out_nodes;
  float2* out_records;
  int* sources; // per record: the binary leaf order's triangle it copies
  // The sah rule's (CostRows, CountChildren):
  CostRecord* records; // per node: its spread and triangle range, for its parent
  unsigned* choices;   // CostChoices packed (pack_choices)
  unsigned* arrivals;
};

// A child of a wide node: a leaf (node -1) of the triangles first .. first + count - 1, or
// the wide node made of binary node `node`; its box is child `from & 1` of binary node
// `from >> 1`.
struct WideChild {
  Aabb box;
  int node, first, count, from;
};

// A wide node's children at fixed places: binary child c's at place 2c, or, opened, its two
// children at places 2c and 2c + 1; `present` has a bit per place that holds one, `slot` the
// octant slot of each. Fixed places and unrolled loops keep all of it in registers on the GPU.
template <int Places = k_width> struct WideChildren {
  WideChild child[Places];
  int slot[Places];
  unsigned present = 0;
};

// The octant slots of the children of the wide node made of binary node `node`.
RT_HD inline void assign_child_slots(const BvhNode& node, WideChildren<>& out) {
  Aabb box = node.box[0];
  box.grow(node.box[1]);
  Aabb boxes[k_width];
  RT_UNROLL
  for (int c = 0; c < k_width; ++c) boxes[c] = out.child[c].box;
  ch09::assign_slots(box, boxes, out.present, out.slot);
}

// Binary child c of node i, as a leaf of the wide tree or opened further (interior = true).
RT_HD inline WideChild binary_child(const CollapseView& t, const BvhNode& node, int at, int c,
                                    bool& interior) {
  interior = false;
  if (node.is_leaf(c)) return {node.box[c], -1, node.first[c], node.count[c], 2 * at + c};
  const int x = node.first[c];
  const int first = t.range_first[x], count = t.range_end[x] - first;
  interior = count > t.leaf_size;
  return {node.box[c], interior ? x : -1, first, count, 2 * at + c};
}

// The children of the wide node made of binary node i: its binary children, each covering more
// than three triangles opened into its own two; then the octant slots.
RT_HD inline WideChildren<> wide_children(const CollapseView& t, int i) {
  WideChildren<> out;
  const BvhNode node = load_node(&t.nodes[i]);
  RT_UNROLL
  for (int c = 0; c < 2; ++c) {
    if (!node.is_leaf(c) && node.first[c] < 0) continue; // the one-triangle tree's empty side
    bool open = false;
    const WideChild child = binary_child(t, node, i, c, open);
    if (!open) {
      out.child[2 * c] = child;
      out.present |= 1u << (2 * c);
      continue;
    }
    const BvhNode opened = load_node(&t.nodes[child.node]);
    RT_UNROLL
    for (int d = 0; d < 2; ++d) {
      bool interior = false;
      out.child[2 * c + d] = binary_child(t, opened, child.node, d, interior);
      out.present |= 1u << (2 * c + d);
    }
  }
  assign_child_slots(node, out);
  return out;
}

// Calls visit(child, slot, position) for each child in slot order, position counting from 0:
// every loop unrolled, every index fixed.
template <int Places, class Visit>
RT_HD void in_slot_order(const WideChildren<Places>& w, Visit&& visit) {
  int rank[Places];
  RT_UNROLL
  for (int c = 0; c < Places; ++c) {
    rank[c] = 0;
    RT_UNROLL
    for (int d = 0; d < Places; ++d)
      rank[c] += (w.present >> d & 1u) != 0 && w.slot[d] < w.slot[c];
  }
  RT_UNROLL
  for (int p = 0; p < k_width; ++p) RT_UNROLL
  for (int c = 0; c < Places; ++c)
    if ((w.present >> c & 1u) != 0 && rank[c] == p) visit(w.child[c], w.slot[c], p);
}

// The sah rule. A node's choices in one word: bits 2(i - 2) and up, the left share of i
// children (i = 2..4; 0 where fewer cost no more); bits 6-7 the left share of a wide node made
// of it; bit 8, one child means a leaf.
RT_HD inline unsigned pack_choices(const ch09::CostChoices& c, int node_split) {
  unsigned word = unsigned(node_split) << 6 | unsigned(c.as_leaf) << 8;
  RT_UNROLL
  for (int i = 2; i <= k_width; ++i) word |= unsigned(c.split[i - 1]) << (2 * (i - 2));
  return word;
}
RT_HD inline int split_of(unsigned word, int i) { return int(word >> (2 * (i - 2)) & 3u); }
RT_HD inline int node_split_of(unsigned word) { return int(word >> 6 & 3u); }
RT_HD inline bool as_leaf_of(unsigned word) { return (word >> 8 & 1u) != 0; }

// Pass 1 (sah): every node's triangle range and spread, from the bottom up as the refit goes
// (refit.h): a node whose two children are both leaves (or a leaf and the empty side of a
// one-triangle tree) is worked out at once by its thread; one with a single leaf child by
// whichever of its thread and its interior child's climb arrives second; one with none by the
// climb alone. The thread that completes a node climbs on. A node finishes its interior
// children's rows, and so records their choices, as chapter 09's visit does; its own are
// finished by its parent, the root's by itself (always a wide node). Every operation is
// chapter 09's, in its order: the same choices on every backend.
struct CostRows {
  CollapseView t;

  RT_HD void finish(int x) const {
    const BvhNode node = load_node(&t.nodes[x]);
    double rows[2][k_width];
    int first[2], end[2];
    RT_UNROLL
    for (int c = 0; c < 2; ++c) {
      const double area = ch07::half_area_of(node.box[c]);
      if (node.is_leaf(c) || node.first[c] < 0) { // a binary leaf, or no child at all
        const int count = node.is_leaf(c) ? node.count[c] : 0;
        const double cost = count > 0 ? area * count * ch09::k_triangle_cost : 0.0;
        RT_UNROLL
        for (int i = 0; i < k_width; ++i) rows[c][i] = cost;
        first[c] = node.first[c];
        end[c] = node.first[c] + count;
        continue;
      }
      const int m = node.first[c];
      const CostRecord& record = t.records[m];
      ch09::CostSpread<k_width> p;
      const unsigned shares = unsigned(load_published(&record.k));
      RT_UNROLL
      for (int j = 2; j <= k_width; ++j) {
        p.spread[j] = load_published(&record.spread[j - 2]);
        p.k[j] = static_cast<std::uint8_t>(shares >> (2 * (j - 2)) & 3u);
      }
      first[c] = load_published(&record.first);
      end[c] = load_published(&record.end);
      const int count = end[c] - first[c];
      const bool can_be_leaf = count <= t.leaf_size;
      ch09::CostChoices choices;
      ch09::finish_row(area,
                       can_be_leaf ? area * count * ch09::k_triangle_cost
                                   : std::numeric_limits<double>::infinity(),
                       can_be_leaf, p, k_width, rows[c], choices);
      t.choices[m] = pack_choices(choices, p.k[k_width]);
    }
    ch09::CostSpread<k_width> mine;
    ch09::spread_rows(rows[0], rows[1], k_width, mine);
    CostRecord record;
    unsigned shares = 0;
    RT_UNROLL
    for (int j = 2; j <= k_width; ++j) {
      record.spread[j - 2] = mine.spread[j];
      shares |= unsigned(mine.k[j]) << (2 * (j - 2));
    }
    record.k = int(shares);
    record.first = first[0];
    record.end = node.first[1] < 0 && !node.is_leaf(1) ? end[0] : end[1];
    t.records[x] = record;
    if (x == 0) t.choices[0] = pack_choices(ch09::CostChoices{}, mine.k[k_width]);
  }

  // [listing:cost_climb]
  RT_HD void operator()(int i) const {
    const BvhNode& node = t.nodes[i];
    const int ends = (node.count[0] > 0) + (node.count[1] > 0 || node.first[1] < 0);
    if (ends == 0 || (ends == 1 && !second_arrival(&t.arrivals[i]))) return;
    for (int x = i;;) { // this thread completed node x
      finish(x);
      if (t.parents[x] < 0) break;
      x = t.parents[x] >> 1;
      if (!second_arrival(&t.arrivals[x])) break;
    }
  }
  // [/listing:cost_climb]
};

// [listing:find_wide]
// Whether node i is a wide node under the sah rule, from the root down along its path (read
// first as the bits of its ancestors' child slots). At a wide node, its children get the
// shares of its left and right side; a node given s children takes fewer while fewer cost no
// more; one child is a leaf (and nothing below it is a wide node) or a wide node; more are
// shared again between its two sides. Chapter 09's collect, followed down one path.
RT_HD inline bool find_wide(const CollapseView& t, int i) {
  std::uint64_t path = 0; // a tree passing chapter 07's checker is at most 64 deep
  int depth = 0;
  for (int x = i; x != 0; x = t.parents[x] >> 1, ++depth)
    path = path << 1 | unsigned(t.parents[x] & 1);
  int x = 0, share = 0; // share 0: x is a wide node
  for (int d = 0; d < depth; ++d, path >>= 1) {
    const int c = int(path & 1u);
    const unsigned word = t.choices[x];
    const int total = share == 0 ? k_width : share;
    const int left = share == 0 ? node_split_of(word) : split_of(word, share);
    int s = c == 0 ? left : total - left;
    x = t.nodes[x].first[c];
    const unsigned below = t.choices[x];
    while (s > 1 && split_of(below, s) == 0) --s;
    if (s == 1 && as_leaf_of(below)) return false;
    share = s == 1 ? 0 : s;
  }
  return share == 0;
}
// [/listing:find_wide]

// A wide node's children under the sah rule: chapter 09's collect, unrolled over fixed
// places so that everything stays in registers (an array indexed at run time would go to
// local memory, "The collapse and local memory"). Shares of four children halve at most three
// times (3 = 1 + 2, 2 = 1 + 1), so the children of a side at place p, opened, go to places p
// and p + step / 2: eight places for at most four children, in collect's order, then moved to
// places 0 to 3 in that order.
RT_HD inline WideChildren<> sah_children(const CollapseView& t, int i) {
  constexpr int k_places = 8;
  int edge[k_places], share[k_places]; // share 0: no child at that place
  unsigned word[k_places];
  RT_UNROLL
  for (int p = 0; p < k_places; ++p) edge[p] = share[p] = word[p] = 0;
  const int root_split = node_split_of(t.choices[i]);
  edge[0] = 2 * i;
  share[0] = root_split;
  edge[4] = 2 * i + 1;
  share[4] = k_width - root_split;
  RT_UNROLL
  for (int level = 0; level < 3; ++level) { // sides at places 0, 4; then 0, 2, 4, 6; then all
    const int step = 4 >> level;
    RT_UNROLL
    for (int p = 0; p < k_places; p += step) {
      if (share[p] == 0) continue;
      const BvhNode& parent = t.nodes[edge[p] >> 1];
      const int c = edge[p] & 1, m = parent.first[c];
      if (parent.is_leaf(c)) continue;
      if (m < 0) { // the one-triangle tree's empty side: no child
        share[p] = 0;
        continue;
      }
      word[p] = t.choices[m];
      int s = share[p];
      while (s > 1 && split_of(word[p], s) == 0) --s;
      share[p] = s;
      if (s == 1 || level == 2) continue; // one child: kept whole (level 2 has only those)
      const int k = split_of(word[p], s);
      edge[p] = 2 * m;
      share[p] = k;
      edge[p + step / 2] = 2 * m + 1;
      share[p + step / 2] = s - k;
    }
  }
  int rank[k_places];
  RT_UNROLL
  for (int p = 0, before = 0; p < k_places; before += share[p] != 0, ++p) rank[p] = before;
  WideChildren<> out;
  RT_UNROLL
  for (int q = 0; q < k_width; ++q) RT_UNROLL
  for (int p = q; p < k_places; ++p) {
    if (share[p] == 0 || rank[p] != q) continue;
    const BvhNode& parent = t.nodes[edge[p] >> 1];
    const int c = edge[p] & 1, m = parent.first[c];
    WideChild child{parent.box[c], -1, m, parent.count[c], edge[p]};
    if (!parent.is_leaf(c)) {
      const CostRecord& record = t.records[m];
      child.node = as_leaf_of(word[p]) ? -1 : m;
      child.first = record.first;
      child.count = record.end - record.first;
    }
    out.child[q] = child;
    out.present |= 1u << q;
  }
  assign_child_slots(load_node(&t.nodes[i]), out);
  return out;
}

// Pass 1 (depth): each node's triangle range (its leftmost and rightmost leaves, walked
// down to) and whether it is a wide node: the root, or covering more than three triangles at
// even depth (walked up to the root).
struct MeasureNodes {
  CollapseView t;
  RT_HD void operator()(int i) const {
    if (i == 0) {
      t.is_wide[0] = 1;
      return;
    }
    int left = i, right = i;
    while (!t.nodes[left].is_leaf(0)) left = t.nodes[left].first[0];
    while (!t.nodes[right].is_leaf(1)) right = t.nodes[right].first[1];
    t.range_first[i] = t.nodes[left].first[0];
    t.range_end[i] = t.nodes[right].first[1] + t.nodes[right].count[1];
    int depth = 0;
    for (int x = i; x != 0; x = t.parents[x] >> 1) ++depth;
    t.is_wide[i] = depth % 2 == 0 && t.range_end[i] - t.range_first[i] > t.leaf_size;
  }
};

// [listing:wide_order]
// Pass 2: each wide node's children in slot order, kept, and its interior children and leaf
// triangles counted for the scans. Under the sah rule each node first finds whether it is a
// wide node (find_wide), and records it for the passes after.
struct CountChildren {
  CollapseView t;
  bool sah;
  RT_HD void operator()(int i) const {
    int interior = 0, triangles = 0;
    // Under the sah rule a node of at most leaf_size triangles below the root is never a wide
    // node: as one child it costs more as a wide node (its area, and more) than as a leaf
    // (0.9 of its area at most), so only larger ones look for their path.
    const bool wide =
        sah ? i == 0 || (t.records[i].end - t.records[i].first > t.leaf_size && find_wide(t, i))
            : t.is_wide[i] != 0;
    if (sah) t.is_wide[i] = wide;
    if (wide) {
      WideOrder order;
      RT_UNROLL
      for (int p = 0; p < k_width; ++p)
        order.from[p] = order.target[p] = order.count[p] = order.slot[p] = -1;
      const auto keep = [&](const WideChild& child, int slot, int p) {
        const bool inner = child.node >= 0;
        order.from[p] = child.from;
        order.target[p] = inner ? child.node : child.first;
        order.count[p] = inner ? 0 : child.count;
        order.slot[p] = slot;
        interior += inner;
        triangles += inner ? 0 : child.count;
      };
      if (sah)
        in_slot_order(sah_children(t, i), keep);
      else
        in_slot_order(wide_children(t, i), keep);
      t.orders[i] = order;
    }
    t.interior_counts[i] = interior;
    t.leaf_counts[i] = triangles;
  }
};
// [/listing:wide_order]

// Pass 3: each wide node numbers its interior children, in slot order, from its child_base.
struct NumberChildren {
  CollapseView t;
  RT_HD void operator()(int i) const {
    if (i == 0) t.wide_index[0] = 0;
    if (!t.is_wide[i]) return;
    const WideOrder order = t.orders[i];
    int next = 1 + t.interior_offsets[i];
    RT_UNROLL
    for (int p = 0; p < k_width; ++p)
      if (order.from[p] >= 0 && order.count[p] == 0) t.wide_index[order.target[p]] = next++;
  }
};

// Pass 4: each wide node written at its number, and for each of its leaves' triangles, from
// its triangle_base, the place of the triangle to copy there; pass 5 copies them, a thread per
// record, where a thread of this pass would copy up to twelve 40-byte records one after
// another while the three threads in four that hold no wide node wait.
struct WriteWideNodes {
  CollapseView t;
  RT_HD void operator()(int i) const {
    if (!t.is_wide[i]) return;
    const WideOrder order = t.orders[i];
    WideNode<k_width> node;
    std::memset(&node, 0, sizeof node); // the padding too: the same bytes on both backends
    node.child_base = 1 + t.interior_offsets[i];
    node.triangle_base = t.triangle_offsets[i];
    int offset = 0;
    RT_UNROLL
    for (int p = 0; p < k_width; ++p) {
      if (order.from[p] < 0) { // an empty child
        ch09::set_child_box(node, p, Aabb{});
        continue;
      }
      ch09::set_child_box(node, p, t.nodes[order.from[p] >> 1].box[order.from[p] & 1]);
      if (order.count[p] == 0) {
        node.meta[p] = ch09::interior_meta(order.slot[p]);
        node.imask = static_cast<std::uint8_t>(node.imask | (1u << order.slot[p]));
        continue;
      }
      node.meta[p] = ch09::leaf_meta(order.count[p], offset);
      for (int k = 0; k < order.count[p]; ++k, ++offset)
        t.sources[node.triangle_base + offset] = order.target[p] + k;
    }
    t.out_nodes[t.wide_index[i]] = node;
  }
};

// Pass 5: a thread per record, its triangle copied from where pass 4 said. Neighbouring
// records come from neighbouring triangles (both orders are depth first), so the reads as well
// as the writes of a warp fall on few cache lines.
struct GatherRecords {
  CollapseView t;
  RT_HD void operator()(int k) const {
    const int from = t.sources[k];
    ch09::PackedTriangles::write(t.out_records + ch09::PackedTriangles::k_records * k,
                                 t.triangles != nullptr ? t.triangles[from] : TriangleF{},
                                 t.triangle_ids[from]);
  }
};

// The number of wide nodes: the root and every interior child.
struct CountWideNodes {
  const int* interior_offsets;
  const int* interior_counts;
  int last;
  int* total;
  RT_HD void operator()(int) const {
    *total = 1 + interior_offsets[last] + interior_counts[last];
  }
};

std::size_t scan_scratch_bytes(int n) {
  std::size_t bytes = 0;
  RT_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, static_cast<int*>(nullptr),
                                              static_cast<int*>(nullptr), n));
  return std::max<std::size_t>(bytes, 1);
}

// The first n entries of `in`, scanned into `out`.
void exclusive_scan(Backend backend, const BackendArray<int>& in, BackendArray<int>& out,
                    BackendArray<unsigned char>& scratch, int n) {
  if (backend == Backend::cpu) {
    std::exclusive_scan(in.data(), in.data() + n, out.data(), 0);
    return;
  }
  std::size_t bytes = scratch.size();
  RT_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(scratch.data(), bytes, in.data(), out.data(), n));
}

} // namespace

TreeArrays upload_tree(Backend backend, const ch07::Bvh& bvh) {
  TreeArrays tree;
  tree.nodes = BackendArray<BvhNode>(backend, std::span<const BvhNode>(bvh.nodes));
  tree.parents = BackendArray<int>(backend, bvh.nodes.size());
  tree.triangles = BackendArray<TriangleF>(backend, std::span<const TriangleF>(bvh.triangles));
  tree.triangle_ids = BackendArray<int>(backend, std::span<const int>(bvh.triangle_ids));
  tree.arrivals = BackendArray<unsigned>(backend, bvh.nodes.size());
  for_each_index(backend, static_cast<int>(bvh.nodes.size()),
                 LinkParents{tree.nodes.data(), tree.parents.data()});
  return tree;
}

WideCollapse::WideCollapse(Backend backend, int triangle_count, int leaf_size,
                           CollapseRule rule)
    : backend_(backend), triangle_count_(triangle_count), leaf_size_(leaf_size),
      capacity_(std::max(1, triangle_count - 1)), rule_(rule),
      range_first_(backend, rule == CollapseRule::depth ? capacity_ : 0),
      range_end_(backend, rule == CollapseRule::depth ? capacity_ : 0),
      is_wide_(backend, capacity_), interior_counts_(backend, capacity_),
      leaf_counts_(backend, capacity_), interior_offsets_(backend, capacity_),
      triangle_offsets_(backend, capacity_), wide_index_(backend, capacity_),
      orders_(backend, capacity_), wide_total_(backend, 1), nodes_(backend, capacity_),
      records_(backend, std::size_t(5) * std::max(1, triangle_count)),
      sources_(backend, std::max(1, triangle_count)),
      scratch_(backend, backend == Backend::gpu ? scan_scratch_bytes(capacity_) : 0),
      records_sah_(backend, rule == CollapseRule::sah ? capacity_ : 0),
      choices_(backend, rule == CollapseRule::sah ? capacity_ : 0),
      arrivals_(backend, rule == CollapseRule::sah ? capacity_ : 0) {
  if (leaf_size < 1 || leaf_size > k_wide_leaf_triangles)
    throw UsageError("a wide leaf takes 1 to " + std::to_string(k_wide_leaf_triangles) +
                     " triangles, not " + std::to_string(leaf_size));
}

void WideCollapse::run(const TreeArrays& binary) {
  const int n = static_cast<int>(binary.nodes.size());
  if (n > capacity_ || static_cast<int>(binary.triangles.size()) != triangle_count_)
    throw Error("WideCollapse: a tree of another size than the arrays were made for");
  run(binary.nodes.data(), binary.parents.data(), n, binary.triangles.data(),
      binary.triangle_ids.data());
}

void WideCollapse::run(const BvhNode* nodes, const int* parents, int node_count,
                       const TriangleF* triangles, const int* ids) {
  const int n = node_count;
  if (n > capacity_) throw Error("WideCollapse: a tree larger than the arrays were made for");
  if (n == 0) return;
  const CollapseView t{nodes,
                       parents,
                       triangles,
                       ids,
                       leaf_size_,
                       range_first_.data(),
                       range_end_.data(),
                       is_wide_.data(),
                       interior_counts_.data(),
                       leaf_counts_.data(),
                       interior_offsets_.data(),
                       triangle_offsets_.data(),
                       wide_index_.data(),
                       orders_.data(),
                       nodes_.data(),
                       records_.data(),
                       sources_.data(),
                       records_sah_.data(),
                       choices_.data(),
                       arrivals_.data()};
  const bool sah = rule_ == CollapseRule::sah;
  if (sah) {
    arrivals_.fill_bytes(0);
    for_each_index(backend_, n, CostRows{t});
  } else {
    for_each_index(backend_, n, MeasureNodes{t});
  }
  for_each_index(backend_, n, CountChildren{t, sah});
  exclusive_scan(backend_, interior_counts_, interior_offsets_, scratch_, n);
  exclusive_scan(backend_, leaf_counts_, triangle_offsets_, scratch_, n);
  for_each_index(backend_, n, NumberChildren{t});
  for_each_index(backend_, n, WriteWideNodes{t});
  for_each_index(backend_, triangle_count_, GatherRecords{t});
  for_each_index(backend_, 1,
                 CountWideNodes{interior_offsets_.data(), interior_counts_.data(), n - 1,
                                wide_total_.data()});
}

ch09::Wide4PackedBvh::View WideCollapse::view() const {
  return {nodes_.data(), records_.data(), capacity_};
}

ch09::Wide4PackedBvh WideCollapse::to_host() const {
  ch09::Wide4PackedBvh tree;
  tree.nodes = nodes_.to_host();
  tree.nodes.resize(static_cast<std::size_t>(wide_total_.to_host()[0]));
  tree.triangles = records_.to_host();
  tree.triangles.resize(std::size_t(5) * triangle_count_);
  fill_wide_stats(tree);
  return tree;
}

const char* to_string(CollapseRule rule) { return rule == CollapseRule::sah ? "sah" : "depth"; }

CollapseRule parse_collapse_rule(const std::string& name) {
  if (name == "sah") return CollapseRule::sah;
  if (name == "depth") return CollapseRule::depth;
  throw UsageError("the collapse rules are sah and depth, not '" + name + "'");
}

ch09::Wide4PackedBvh collapse_to_wide4(Backend backend, const ch07::Bvh& binary,
                                       CollapseRule rule) {
  for (const BvhNode& node : binary.nodes)
    for (int c = 0; c < 2; ++c)
      if (node.count[c] > k_wide_leaf_triangles)
        throw InputError("collapse: a binary leaf of " + std::to_string(node.count[c]) +
                         " triangles; a wide leaf holds at most " +
                         std::to_string(k_wide_leaf_triangles));
  if (binary.nodes.empty()) return {};
  const TreeArrays arrays = upload_tree(backend, binary);
  WideCollapse collapse(backend, static_cast<int>(binary.triangles.size()),
                        k_wide_leaf_triangles, rule);
  BackendStopwatch clock(backend); // build time: events around the kernels, or wall time
  collapse.run(arrays);
  const double ms = clock.milliseconds();
  ch09::Wide4PackedBvh tree = collapse.to_host();
  tree.stats.build_ms = ms;
  return tree;
}

void fill_wide_stats(ch09::Wide4PackedBvh& tree) {
  ch09::WideStats stats;
  stats.build_ms = tree.stats.build_ms;
  stats.nodes = static_cast<int>(tree.nodes.size());
  std::vector<int> depth(tree.nodes.size(), 0);
  long long children = 0, leaf_triangles = 0;
  double cost = 0.0, root_area = 0.0;
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) { // parents come before children
    const ch09::WideNode<4>& node = tree.nodes[i];
    Aabb box;
    int interior = 0;
    for (int c = 0; c < 4 && node.meta[c] != 0; ++c) {
      const Aabb child = ch09::child_box_of(node, c);
      box.grow(child);
      ++children;
      if (ch09::is_interior_meta(node.meta[c])) {
        depth[node.child_base + interior++] = depth[i] + 1;
        continue;
      }
      const int count = std::popcount(unsigned(node.meta[c] >> 5));
      ++stats.leaves;
      leaf_triangles += count;
      cost += ch07::half_area_of(child) * count * ch09::k_triangle_cost;
    }
    cost += ch07::half_area_of(box) * ch09::k_node_cost;
    if (i == 0) root_area = ch07::half_area_of(box);
    stats.depth = std::max(stats.depth, depth[i]);
  }
  if (stats.nodes > 0) stats.children_per_node = double(children) / stats.nodes;
  stats.triangles_per_leaf = double(leaf_triangles) / double(std::max(1, stats.leaves));
  stats.sah_cost = root_area > 0.0 ? cost / root_area : cost;
  if (leaf_triangles > 0)
    stats.bytes_per_triangle = double(tree.nodes.size() * sizeof(ch09::WideNode<4>) +
                                      tree.triangles.size() * sizeof(float2)) /
                               double(leaf_triangles);
  tree.stats = stats;
}

} // namespace rt::ch10
