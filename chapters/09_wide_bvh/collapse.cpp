// Chapter 09: the collapse of a binary tree into a wide one, and its layout. See collapse.h.
#include "collapse.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

#include "bvh_build.h"
#include "octant_slots.h"
#include "rt/error.h"

namespace rt::ch09 {

const char* to_string(Collapse collapse) {
  return collapse == Collapse::sah ? "sah" : "greedy";
}

namespace {

constexpr double k_inf = std::numeric_limits<double>::infinity();

// Whether ids[k] is the first of its value in ids[first..k].
bool first_in_range(const std::vector<int>& ids, int first, int k) {
  for (int j = first; j < k; ++j)
    if (ids[j] == ids[k]) return false;
  return true;
}

// Chapter 07's tree as one entry per node and per leaf, parents before children. A subtree's
// references are consecutive in chapter 07's leaf order: [first, first + count). Its box is
// the one chapter 07 stored for it: for an sbvh tree the box of the clipped parts of its
// triangles, which is all a ray must enter to reach those parts.
struct Entry {
  Aabb box;
  int child[2] = {-1, -1}; // -1: a leaf
  int first = 0, count = 0;
  // The mesh triangles among its references, if it could be a wide leaf (count <= 3): an sbvh
  // subtree may hold one triangle in two of its leaves, and a wide leaf made of it holds
  // that triangle once (its box holds both parts).
  int distinct = 0;
  bool leaf() const { return child[0] < 0; }
};

class Entries {
public:
  explicit Entries(const ch07::Bvh& bvh) {
    if (bvh.nodes.empty()) return;
    const ch07::BvhNode& root = bvh.nodes[0];
    if (root.count[0] > 0 && root.count[1] == 0) // the whole mesh in one leaf
      entries_.push_back({bvh.bounds, {-1, -1}, root.first[0], root.count[0]});
    else
      add_node(bvh, 0, bvh.bounds);
    for (Entry& e : entries_) e.distinct = distinct_triangles(bvh, e);
  }
  const std::vector<Entry>& all() const { return entries_; }

private:
  static int distinct_triangles(const ch07::Bvh& bvh, const Entry& e) {
    if (e.count > k_max_leaf_triangles) return e.count;
    int distinct = 0;
    for (int k = e.first; k < e.first + e.count; ++k)
      distinct += first_in_range(bvh.triangle_ids, e.first, k);
    return distinct;
  }

  int add_node(const ch07::Bvh& bvh, int node, const Aabb& box) {
    const int index = static_cast<int>(entries_.size());
    entries_.push_back({box});
    const ch07::BvhNode n = bvh.nodes[node];
    int child[2];
    for (int c = 0; c < 2; ++c) {
      if (n.is_leaf(c)) {
        child[c] = static_cast<int>(entries_.size());
        entries_.push_back({n.box[c], {-1, -1}, n.first[c], n.count[c]});
      } else {
        child[c] = add_node(bvh, n.first[c], n.box[c]);
      }
    }
    const Entry& left = entries_[child[0]];
    const Entry& right = entries_[child[1]];
    if (right.first != left.first + left.count)
      throw Error("collapse: a binary subtree's triangles are not consecutive");
    entries_[index] = {box, {child[0], child[1]}, left.first, left.count + right.count};
    return index;
  }

  std::vector<Entry> entries_;
};

// A wide node's child, before it has a slot: a binary entry, kept whole as a leaf or made a
// wide node of its own.
struct Pick {
  int entry;
  bool leaf;
};
using Picks = std::vector<Pick>;

// [listing:sah_collapse]
// The SAH collapse (the paper's dynamic programming). For every binary entry n, bottom up, and
// every i = 1..width: cost[n][i] is the least cost of n's triangles as at most i children of a
// wide node (i "roots"). With A(n) n's box area and p(n) its triangle count:
//   leaf(n)        = A(n) p(n) k_triangle_cost    if p(n) <= k_max_leaf_triangles, else inf
//   interior(n)    = A(n) k_node_cost + distribute(n, width)
//   distribute(n, j) = min over 0 < k < j of cost[left][k] + cost[right][j - k]
//   cost[n][1]     = min(leaf(n), interior(n))
//   cost[n][i]     = min(cost[n][i - 1], distribute(n, i))
// Recording which choice won, a wide node made of n takes distribute(n, width)'s children.
class SahCollapse {
public:
  SahCollapse(const std::vector<Entry>& entries, int width)
      : entries_(entries), width_(width), cost_(entries.size()), split_(entries.size()),
        node_split_(entries.size()), as_leaf_(entries.size()) {
    for (int n = static_cast<int>(entries.size()) - 1; n >= 0; --n) price(n);
  }

  // The children of a wide node made of interior entry n.
  Picks children(int n) const {
    Picks out;
    const Entry& e = entries_[n];
    collect(e.child[0], node_split_[n], out);
    collect(e.child[1], width_ - node_split_[n], out);
    return out;
  }

private:
  double distribute(int n, int j, int& best_k) const {
    const Entry& e = entries_[n];
    double best = k_inf;
    for (int k = 1; k < j; ++k) {
      const double c = cost_[e.child[0]][k] + cost_[e.child[1]][j - k];
      if (c < best) {
        best = c;
        best_k = k;
      }
    }
    return best;
  }

  void price(int n) {
    const Entry& e = entries_[n];
    const double area = ch07::half_area_of(e.box);
    const double leaf =
        e.count <= k_max_leaf_triangles ? area * e.distinct * k_triangle_cost : k_inf;
    if (e.leaf()) {
      cost_[n].fill(leaf);
      as_leaf_[n] = true;
      return;
    }
    const double interior = area * k_node_cost + distribute(n, width_, node_split_[n]);
    as_leaf_[n] = leaf <= interior;
    cost_[n][1] = std::min(leaf, interior);
    for (int i = 2; i <= width_; ++i) {
      int k = 0;
      const double spread = distribute(n, i, k);
      const bool fewer = cost_[n][i - 1] <= spread; // on a tie, fewer children
      cost_[n][i] = fewer ? cost_[n][i - 1] : spread;
      split_[n][i] = fewer ? 0 : k;
    }
  }

  void collect(int n, int i, Picks& out) const {
    const Entry& e = entries_[n];
    if (i == 1 || e.leaf()) {
      out.push_back({n, as_leaf_[n] != 0});
    } else if (split_[n][i] == 0) {
      collect(n, i - 1, out);
    } else {
      collect(e.child[0], split_[n][i], out);
      collect(e.child[1], i - split_[n][i], out);
    }
  }

  const std::vector<Entry>& entries_;
  int width_;
  std::vector<std::array<double, k_slots + 1>> cost_; // [n][i], i = 1..width
  std::vector<std::array<int, k_slots + 1>> split_;   // [n][i]: k, or 0 for cost[n][i-1]
  std::vector<int> node_split_;                       // k of distribute(n, width)
  std::vector<unsigned char> as_leaf_;                // cost[n][1] is leaf(n)
};
// [/listing:sah_collapse]

// [listing:greedy_collapse]
// The greedy collapse: start from the binary node's two children and open the one with the
// largest box (replace it by its own two children) until the node has `width` children or
// only binary leaves are left. The binary leaves are the wide leaves.
Picks greedy_children(const std::vector<Entry>& entries, int n, int width) {
  Picks out{{entries[n].child[0], false}, {entries[n].child[1], false}};
  while (static_cast<int>(out.size()) < width) {
    int largest = -1;
    for (int k = 0; k < static_cast<int>(out.size()); ++k)
      if (!entries[out[k].entry].leaf() &&
          (largest < 0 || ch07::half_area_of(entries[out[k].entry].box) >
                              ch07::half_area_of(entries[out[largest].entry].box)))
        largest = k;
    if (largest < 0) break;
    const Entry& opened = entries[out[largest].entry];
    out[largest] = {opened.child[0], false};
    out.push_back({opened.child[1], false});
  }
  for (Pick& p : out) p.leaf = entries[p.entry].leaf();
  return out;
}
// [/listing:greedy_collapse]

// Lays the chosen children out, depth first: a node's interior children get consecutive
// nodes, its leaves consecutive triangles, both in slot order.
class Layout {
public:
  Layout(const ch07::Bvh& binary, const std::vector<Entry>& entries, WideLayout& out)
      : binary_(binary), entries_(entries), out_(out) {}

  template <class ChildrenOf>
  void emit(int node, const Picks& picks, ChildrenOf children_of, int depth) {
    out_.stats.depth = std::max(out_.stats.depth, depth);
    if (depth > k_wide_stack_size)
      throw Error("collapse: a node at depth " + std::to_string(depth) +
                  " is beyond the traversal stack's bound");
    Aabb boxes[k_slots] = {};
    for (std::size_t c = 0; c < picks.size(); ++c) boxes[c] = entries_[picks[c].entry].box;
    int slot_of[k_slots];
    assign_slots(out_.nodes[node].box, boxes, (1u << picks.size()) - 1u, slot_of);
    int in_slot[k_slots];
    std::fill(std::begin(in_slot), std::end(in_slot), -1);
    for (int c = 0; c < static_cast<int>(picks.size()); ++c) in_slot[slot_of[c]] = c;

    SlotNode n = out_.nodes[node];
    n.child_base = static_cast<int>(out_.nodes.size());
    n.triangle_base = static_cast<int>(out_.triangles.size());
    std::vector<std::pair<int, int>> interior; // (node, entry), in slot order
    for (int s = 0; s < k_slots; ++s) {
      if (in_slot[s] < 0) continue;
      const Pick& p = picks[in_slot[s]];
      const Entry& e = entries_[p.entry];
      n.child_box[s] = e.box;
      if (p.leaf) {
        n.meta[s] =
            leaf_meta(e.distinct, static_cast<int>(out_.triangles.size()) - n.triangle_base);
        for (int k = e.first; k < e.first + e.count; ++k) {
          if (!first_in_range(binary_.triangle_ids, e.first, k)) continue;
          out_.triangles.push_back(binary_.triangles[k]);
          out_.triangle_ids.push_back(binary_.triangle_ids[k]);
        }
        ++out_.stats.leaves;
        sah_ += ch07::half_area_of(e.box) * e.distinct * k_triangle_cost;
      } else {
        n.meta[s] = interior_meta(s);
        n.imask = static_cast<std::uint8_t>(n.imask | (1u << s));
        interior.emplace_back(static_cast<int>(out_.nodes.size()), p.entry);
        SlotNode child;
        child.box = e.box;
        out_.nodes.push_back(child);
      }
    }
    out_.nodes[node] = n;
    children_ += static_cast<long long>(picks.size());
    sah_ += ch07::half_area_of(n.box) * k_node_cost;
    for (const auto& [child, entry] : interior)
      emit(child, children_of(entry), children_of, depth + 1);
  }

  double sah() const { return sah_; }
  long long children() const { return children_; }

private:
  const ch07::Bvh& binary_;
  const std::vector<Entry>& entries_;
  WideLayout& out_;
  double sah_ = 0.0; // unnormalised: areas, not area ratios
  long long children_ = 0;
};

} // namespace

ch07::BuildOptions binary_options(Collapse collapse, const ch07::BuildOptions& base) {
  ch07::BuildOptions options = base;
  options.max_leaf_size = collapse == Collapse::sah ? 1 : k_max_leaf_triangles;
  return options;
}

WideLayout collapse(const ch07::Bvh& binary, int width, Collapse method) {
  const auto start = std::chrono::steady_clock::now();
  if (width < 2 || width > k_slots)
    throw InputError("a wide node has 2 to " + std::to_string(k_slots) + " children, not " +
                     std::to_string(width));
  WideLayout out;
  out.width = width;
  out.stats.split = binary.options.method;
  out.stats.triangles = binary.stats.triangles;
  const Entries entries(binary);
  const std::vector<Entry>& all = entries.all();
  for (const Entry& e : all)
    if (e.leaf() && e.count > k_max_leaf_triangles)
      throw InputError("collapse: a binary leaf of " + std::to_string(e.count) +
                       " triangles; a wide leaf holds at most " +
                       std::to_string(k_max_leaf_triangles));
  if (all.empty()) return out;

  SlotNode root;
  root.box = binary.bounds;
  out.nodes.push_back(root);
  Layout layout(binary, all, out);
  if (all[0].leaf()) { // the whole mesh is one leaf: a root with that leaf alone
    const auto no_children = [](int) { return Picks{}; };
    layout.emit(0, {{0, true}}, no_children, 0);
  } else if (method == Collapse::sah) {
    const SahCollapse sah(all, width);
    const auto children_of = [&](int n) { return sah.children(n); };
    layout.emit(0, children_of(0), children_of, 0);
  } else {
    const auto children_of = [&](int n) { return greedy_children(all, n, width); };
    layout.emit(0, children_of(0), children_of, 0);
  }
  WideStats& s = out.stats;
  s.references = static_cast<long long>(out.triangles.size());
  s.nodes = static_cast<int>(out.nodes.size());
  s.children_per_node = double(layout.children()) / double(s.nodes);
  s.triangles_per_leaf = double(out.triangles.size()) / double(std::max(1, s.leaves));
  const double root_area = ch07::half_area_of(binary.bounds);
  s.sah_cost = root_area > 0.0 ? layout.sah() / root_area : layout.sah();
  s.build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
          .count();
  return out;
}

WideLayout build_wide_layout(const ch04::Mesh& mesh, int width, Collapse method,
                             const ch07::BuildOptions& base) {
  const ch07::Bvh binary = ch07::build_bvh(mesh, binary_options(method, base));
  WideLayout layout = collapse(binary, width, method);
  layout.stats.build_ms += binary.stats.build_ms;
  return layout;
}

} // namespace rt::ch09
