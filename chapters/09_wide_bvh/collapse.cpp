// Chapter 09: the collapse of a binary tree into a wide one, and its layout. See collapse.h.
#include "collapse.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "bvh_build.h"
#include "octant_slots.h"
#include "rt/backend.h"
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

// The mesh triangles among the references [first, first + count): an sbvh subtree may hold one
// triangle in two of its leaves, and a wide leaf made of it holds that triangle once (its box
// holds both parts). Counted only where the references could be a wide leaf.
int distinct_triangles(const std::vector<int>& ids, int first, int count) {
  if (count > k_max_leaf_triangles) return count;
  int distinct = 0;
  for (int k = first; k < first + count; ++k) distinct += first_in_range(ids, first, k);
  return distinct;
}

// Chapter 07's tree as the collapse reads it. What a wide node's child is made of is a child of
// a binary node, an "edge" numbered 2 * node + c: kept whole as a wide leaf, or made a wide
// node of its own. Its box is the one chapter 07 stored for it: for an sbvh tree the box of the
// clipped parts of its triangles, which is all a ray must enter to reach those parts. A
// subtree's references are consecutive in chapter 07's leaf order: [first, first + count).
class BinaryTree {
public:
  explicit BinaryTree(const ch07::Bvh& bvh)
      : bvh_(bvh), range_first_(bvh.nodes.size()), range_count_(bvh.nodes.size()) {}

  static int edge(int node, int c) { return 2 * node + c; }
  const ch07::BvhNode& node(int n) const { return bvh_.nodes[n]; }
  int node_count() const { return static_cast<int>(bvh_.nodes.size()); }
  const Aabb& box(int e) const { return bvh_.nodes[e >> 1].box[e & 1]; }
  bool leaf(int e) const { return bvh_.nodes[e >> 1].is_leaf(e & 1); }
  int child_node(int e) const { return bvh_.nodes[e >> 1].first[e & 1]; } // interior edges
  int first(int e) const {
    return leaf(e) ? node(e >> 1).first[e & 1] : range_first_[child_node(e)];
  }
  int count(int e) const {
    return leaf(e) ? node(e >> 1).count[e & 1] : range_count_[child_node(e)];
  }
  int distinct(int e) const {
    return distinct_triangles(bvh_.triangle_ids, first(e), count(e));
  }
  const std::vector<int>& triangle_ids() const { return bvh_.triangle_ids; }
  const std::vector<TriangleF>& triangles() const { return bvh_.triangles; }

  // The references below interior node n, from its children's (which must be known): the
  // bottom-up pass calls it for every node after its interior children.
  void set_range(int n) {
    const ch07::BvhNode& x = node(n);
    for (int c = 0; c < 2; ++c)
      if (!x.is_leaf(c) && !(x.first[c] > n && x.first[c] < node_count()))
        throw Error("collapse: the binary tree is not in depth-first order");
    const int left = edge(n, 0), right = edge(n, 1);
    if (first(right) != first(left) + count(left))
      throw Error("collapse: a binary subtree's triangles are not consecutive");
    range_first_[n] = first(left);
    range_count_[n] = count(left) + count(right);
  }

  // One past the last node of interior node n's subtree: chapter 07 writes a subtree's nodes
  // depth first, so they are the numbers from n up to its last node on the right.
  int subtree_end(int n) const {
    for (;;) {
      const ch07::BvhNode& x = node(n);
      if (!x.is_leaf(1))
        n = x.first[1];
      else if (!x.is_leaf(0))
        n = x.first[0];
      else
        return n + 1;
    }
  }

private:
  const ch07::Bvh& bvh_;
  std::vector<int> range_first_, range_count_; // per interior node
};

// How many pieces each thread gets, about, and the smallest piece worth handing out: as in
// chapter 07's build (bvh_build.cpp), a handful per thread, so that uneven pieces still finish
// together.
constexpr int k_pieces_per_thread = 4;
constexpr int k_min_piece = 2048;

// [listing:bottom_up]
// How the interior nodes of the binary tree are visited bottom up, each after its interior
// children. In chapter 07's depth-first order a child's number is larger than its parent's,
// and a subtree's nodes are consecutive numbers, so a subtree visited in decreasing number is
// visited bottom up. On one thread the whole tree is one piece. On several, the subtrees of at
// most `piece` nodes just below the top are the pieces, handed to the threads, and the few
// nodes above them (`top`) are visited after, one after the other, in decreasing number. Each
// visit reads only what its children's visits left, so every node sees the very same values
// whichever thread visited its children, and when.
struct BottomUpPlan {
  std::vector<std::pair<int, int>> pieces; // [first, end) node ranges, largest first
  std::vector<int> top;                    // in decreasing number
};

BottomUpPlan plan_bottom_up(const BinaryTree& tree, int threads) {
  const int count = tree.node_count();
  const int piece = std::max(k_min_piece, count / (k_pieces_per_thread * threads));
  BottomUpPlan plan;
  if (threads == 1 || count <= piece) {
    plan.pieces.emplace_back(0, count);
    return plan;
  }
  plan.top.push_back(0); // parents before children while it grows
  for (std::size_t k = 0; k < plan.top.size(); ++k) {
    const ch07::BvhNode& x = tree.node(plan.top[k]);
    for (int c = 0; c < 2; ++c) {
      if (x.is_leaf(c)) continue;
      const int child = x.first[c];
      if (!(child > plan.top[k] && child < count))
        throw Error("collapse: the binary tree is not in depth-first order");
      const int end = tree.subtree_end(child);
      if (end - child <= piece)
        plan.pieces.emplace_back(child, end);
      else
        plan.top.push_back(child);
    }
  }
  std::stable_sort(plan.pieces.begin(), plan.pieces.end(), [](const auto& a, const auto& b) {
    return a.second - a.first > b.second - b.first;
  });
  std::sort(plan.top.rbegin(), plan.top.rend());
  return plan;
}

// visit(n, part) for every interior node n: part k for the nodes of piece k, pieces.size()
// for the top.
template <class Visit>
void visit_bottom_up(const BottomUpPlan& plan, int threads, Visit visit) {
  const int top_part = static_cast<int>(plan.pieces.size());
  const auto visit_piece = [&](std::size_t k) {
    for (int n = plan.pieces[k].second - 1; n >= plan.pieces[k].first; --n)
      visit(n, static_cast<int>(k));
  };
  if (plan.pieces.size() == 1 && plan.top.empty())
    visit_piece(0);
  else
    for_each_index_cpu(plan.pieces.size(), visit_piece, threads, "parts");
  for (const int n : plan.top) visit(n, top_part);
}
// [/listing:bottom_up]

// A wide node's child, before it has a slot: a binary edge, kept whole as a leaf or made a
// wide node of its own.
struct Pick {
  int edge;
  bool leaf;
};
struct Picks {
  Pick pick[k_slots];
  int count = 0;
  void push(Pick p) { pick[count++] = p; }
};

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
// An entry is an edge of the binary tree: a binary leaf costs leaf(n) for every i. A binary
// node's box, and so A(n), is stored in its parent: its visit leaves distribute(n, j) for
// every j (a Partial), and its parent's visit finishes its row. A row is read only by the
// parent's visit, so the rows need not be kept: in decreasing node number a node's children
// are the last two subtrees finished, and their Partials the top two of a stack. What stays
// for the layout is each node's choices, a few bytes, not its costs.
class SahCollapse {
public:
  SahCollapse(BinaryTree& tree, int width, int threads)
      : tree_(tree), width_(width), split_(table<std::uint8_t>(tree.node_count() * width_)),
        node_split_(table<std::uint8_t>(tree.node_count())),
        as_leaf_(table<std::uint8_t>(tree.node_count())) {
    const BottomUpPlan plan = plan_bottom_up(tree, threads);
    stacks_.resize(plan.pieces.size() + 1);
    visit_bottom_up(plan, threads, [&](int n, int part) {
      tree_.set_range(n);
      const auto partial_of = [&](int child) -> Partial {
        std::vector<Partial>& stack = stacks_[part];
        if (part < static_cast<int>(plan.pieces.size())) { // in a piece: the stack's top
          if (stack.empty() || stack.back().node != child)
            throw Error("collapse: the binary tree is not in depth-first order");
          const Partial p = stack.back();
          stack.pop_back();
          return p;
        }
        for (std::size_t k = 0; k < plan.pieces.size(); ++k) // a piece's root, or the top's
          if (plan.pieces[k].first == child) return stacks_[k].back();
        for (const Partial& p : stack)
          if (p.node == child) return p;
        throw Error("collapse: the binary tree is not in depth-first order");
      };
      stacks_[part].push_back(visit(n, partial_of));
    });
    node_split_[0] = stacks_[plan.top.empty() ? 0 : plan.pieces.size()].back().k[width_];
  }

  // The children of a wide node made of interior node n.
  Picks children(int n) const {
    Picks out;
    collect(BinaryTree::edge(n, 0), node_split_[n], out);
    collect(BinaryTree::edge(n, 1), width_ - node_split_[n], out);
    return out;
  }

private:
  // Interior node n's distribute(n, j) for j = 2..width, and the k that gives each.
  struct Partial : CostSpread<k_slots> {
    int node;
  };

  // Millions of entries: left uninitialised (every one is written before it is read), so the
  // pages are first touched by the thread that writes them, not zeroed by this one.
  template <class T> static std::unique_ptr<T[]> table(int size) {
    return std::make_unique_for_overwrite<T[]>(static_cast<std::size_t>(size));
  }

  double leaf_cost(int e) const {
    return tree_.count(e) <= k_max_leaf_triangles
               ? ch07::half_area_of(tree_.box(e)) * tree_.distinct(e) * k_triangle_cost
               : k_inf;
  }

  // cost[m][1..width] of the interior node m at the end of edge e, from its Partial; its
  // choices recorded.
  void finish_row(int e, const Partial& p, double* cost) {
    const int m = p.node;
    CostChoices choices;
    ch09::finish_row(ch07::half_area_of(tree_.box(e)), leaf_cost(e),
                     tree_.count(e) <= k_max_leaf_triangles, p, width_, cost, choices);
    node_split_[m] = p.k[width_];
    as_leaf_[m] = choices.as_leaf;
    std::copy_n(choices.split, width_, &split_[std::size_t(m) * width_]);
  }

  // Node n's visit: its children's rows (a binary leaf's repeated, an interior child's
  // finished from its Partial), then n's own Partial.
  template <class PartialOf> Partial visit(int n, PartialOf partial_of) {
    double rows[2][k_slots];
    for (int c = 0; c < 2; ++c) {
      const int e = BinaryTree::edge(n, c);
      if (tree_.leaf(e))
        std::fill(std::begin(rows[c]), std::end(rows[c]), leaf_cost(e));
      else
        finish_row(e, partial_of(tree_.child_node(e)), rows[c]);
    }
    Partial p;
    p.node = n;
    spread_rows(rows[0], rows[1], width_, p);
    return p;
  }

  void collect(int e, int i, Picks& out) const {
    if (tree_.leaf(e)) {
      out.push({e, true});
      return;
    }
    const int n = tree_.child_node(e);
    const int k = split_[std::size_t(n) * width_ + i - 1];
    if (i == 1) {
      out.push({e, as_leaf_[n] != 0});
    } else if (k == 0) {
      collect(e, i - 1, out);
    } else {
      collect(BinaryTree::edge(n, 0), k, out);
      collect(BinaryTree::edge(n, 1), i - k, out);
    }
  }

  BinaryTree& tree_;
  int width_;
  std::unique_ptr<std::uint8_t[]> split_;      // [n][i - 1]: k, or 0 for cost[n][i - 1]
  std::unique_ptr<std::uint8_t[]> node_split_; // k of distribute(n, width)
  std::unique_ptr<std::uint8_t[]> as_leaf_;    // cost[n][1] is leaf(n)
  std::vector<std::vector<Partial>> stacks_;   // per piece, and the top's
};
// [/listing:sah_collapse]

// [listing:greedy_collapse]
// The greedy collapse: start from the binary node's two children and open the one with the
// largest box (replace it by its own two children) until the node has `width` children or
// only binary leaves are left. The binary leaves are the wide leaves.
Picks greedy_children(const BinaryTree& tree, int n, int width) {
  Picks out;
  out.push({BinaryTree::edge(n, 0), false});
  out.push({BinaryTree::edge(n, 1), false});
  while (out.count < width) {
    int largest = -1;
    for (int k = 0; k < out.count; ++k)
      if (!tree.leaf(out.pick[k].edge) &&
          (largest < 0 || ch07::half_area_of(tree.box(out.pick[k].edge)) >
                              ch07::half_area_of(tree.box(out.pick[largest].edge))))
        largest = k;
    if (largest < 0) break;
    const int opened = tree.child_node(out.pick[largest].edge);
    out.pick[largest] = {BinaryTree::edge(opened, 0), false};
    out.push({BinaryTree::edge(opened, 1), false});
  }
  for (int k = 0; k < out.count; ++k) out.pick[k].leaf = tree.leaf(out.pick[k].edge);
  return out;
}
// [/listing:greedy_collapse]

// A piece of the wide tree as one thread writes it: nodes and triangles numbered from 0.
struct Fragment {
  std::vector<SlotNode> nodes;
  std::vector<TriangleF> triangles;
  std::vector<int> triangle_ids;

  // Room for a piece of `references` binary references, so that the arrays are not copied as
  // they grow: at most that many triangles, and (a wide node holding two children or more, the
  // leaves one triangle or more) rarely more nodes than half as many.
  void reserve(int references) {
    nodes.reserve(std::size_t(references) / 2 + 1);
    triangles.reserve(std::size_t(references));
    triangle_ids.reserve(std::size_t(references));
  }
};

// A wide subtree left to the threads: its root `node` of the top (made of `edge`) has its box;
// the rest is written into `fragment`, whose node 0 is that root. `position` and
// `triangle_position` are the top's node and triangle counts when it was handed out: in the
// serial depth-first order, its nodes and triangles come right there.
struct WideSubtree {
  int node = 0, edge = 0, depth = 0;
  int position = 0, triangle_position = 0;
  Fragment fragment;
  int start = 0, triangle_start = 0; // where its nodes and triangles begin in the whole tree
};

// Lays the chosen children out, depth first: a node's interior children get consecutive
// nodes, its leaves consecutive triangles, both in slot order. With a `handoff`, the top of
// the tree does not descend into a wide child of at most that many references: it becomes a
// WideSubtree, laid out later by a thread of its own.
template <class ChildrenOf> class Layout {
public:
  Layout(const BinaryTree& tree, ChildrenOf children_of, Fragment& out, int handoff = 0,
         std::vector<WideSubtree>* subtrees = nullptr)
      : tree_(tree), children_of_(children_of), out_(out), handoff_(handoff),
        subtrees_(subtrees) {}

  void emit(int node, const Picks& picks, int depth) {
    if (depth > k_wide_stack_size)
      throw Error("collapse: a node at depth " + std::to_string(depth) +
                  " is beyond the traversal stack's bound");
    Aabb boxes[k_slots] = {};
    for (int c = 0; c < picks.count; ++c) boxes[c] = tree_.box(picks.pick[c].edge);
    int slot_of[k_slots];
    assign_slots(out_.nodes[node].box, boxes, (1u << picks.count) - 1u, slot_of);
    int in_slot[k_slots];
    std::fill(std::begin(in_slot), std::end(in_slot), -1);
    for (int c = 0; c < picks.count; ++c) in_slot[slot_of[c]] = c;

    SlotNode n = out_.nodes[node];
    n.child_base = static_cast<int>(out_.nodes.size());
    n.triangle_base = static_cast<int>(out_.triangles.size());
    if (subtrees_) {
      subtrees_before_.resize(out_.nodes.size());
      subtrees_before_[node] = static_cast<int>(subtrees_->size());
    }
    std::pair<int, int> interior[k_slots]; // (node, edge), in slot order
    int interior_count = 0;
    for (int s = 0; s < k_slots; ++s) {
      if (in_slot[s] < 0) continue;
      const Pick& p = picks.pick[in_slot[s]];
      n.child_box[s] = tree_.box(p.edge);
      if (p.leaf) {
        const int first = tree_.first(p.edge), count = tree_.count(p.edge);
        const std::vector<int>& ids = tree_.triangle_ids();
        n.meta[s] = leaf_meta(distinct_triangles(ids, first, count),
                              static_cast<int>(out_.triangles.size()) - n.triangle_base);
        for (int k = first; k < first + count; ++k) {
          if (!first_in_range(ids, first, k)) continue;
          out_.triangles.push_back(tree_.triangles()[k]);
          out_.triangle_ids.push_back(ids[k]);
        }
      } else {
        n.meta[s] = interior_meta(s);
        n.imask = static_cast<std::uint8_t>(n.imask | (1u << s));
        interior[interior_count++] = {static_cast<int>(out_.nodes.size()), p.edge};
        SlotNode child;
        child.box = tree_.box(p.edge);
        out_.nodes.push_back(child);
      }
    }
    out_.nodes[node] = n;
    for (int k = 0; k < interior_count; ++k) {
      const auto [child, edge] = interior[k];
      if (subtrees_ && tree_.count(edge) <= handoff_) {
        WideSubtree& subtree = subtrees_->emplace_back();
        subtree.node = child;
        subtree.edge = edge;
        subtree.depth = depth + 1;
        subtree.position = static_cast<int>(out_.nodes.size());
        subtree.triangle_position = static_cast<int>(out_.triangles.size());
      } else {
        emit(child, children_of_(tree_.child_node(edge)), depth + 1);
      }
    }
  }

  // How many subtrees had been handed out when each node of the top got its child_base and
  // triangle_base.
  const std::vector<int>& subtrees_before() const { return subtrees_before_; }

private:
  const BinaryTree& tree_;
  ChildrenOf children_of_;
  Fragment& out_;
  int handoff_;
  std::vector<WideSubtree>* subtrees_;
  std::vector<int> subtrees_before_;
};

// The whole layout in the serial depth-first order: the top's nodes and triangles, with each
// subtree's inserted where the top had `position` nodes and `triangle_position` triangles, and
// every number shifted to match. A subtree's root stays where its parent put it, in the top; a
// number a node of the top wrote is shifted by the subtrees handed out before it wrote it.
void splice(Fragment& top, std::vector<WideSubtree>& subtrees, std::vector<int> subtrees_before,
            int threads, WideLayout& out) {
  const std::size_t count = subtrees.size();
  std::vector<int> node_shift(count + 1, 0), triangle_shift(count + 1, 0);
  for (std::size_t t = 0; t < count; ++t) {
    const Fragment& f = subtrees[t].fragment;
    node_shift[t + 1] = node_shift[t] + static_cast<int>(f.nodes.size()) - 1;
    triangle_shift[t + 1] = triangle_shift[t] + static_cast<int>(f.triangles.size());
    subtrees[t].start = subtrees[t].position + node_shift[t];
    subtrees[t].triangle_start = subtrees[t].triangle_position + triangle_shift[t];
  }
  const int top_nodes = static_cast<int>(top.nodes.size());
  const int top_triangles = static_cast<int>(top.triangles.size());
  out.nodes.resize(std::size_t(top_nodes) + node_shift[count]);
  out.triangles.resize(std::size_t(top_triangles) + triangle_shift[count]);
  out.triangle_ids.resize(out.triangles.size());
  subtrees_before.resize(top.nodes.size(), 0);
  std::vector<int> index_of(top_nodes);
  for (int j = 0, t = 0; j < top_nodes; ++j) {
    for (; t < int(count) && subtrees[t].position <= j; ++t) {
    }
    index_of[j] = j + node_shift[t];
    SlotNode node = top.nodes[j];
    node.child_base += node_shift[subtrees_before[j]];
    node.triangle_base += triangle_shift[subtrees_before[j]];
    out.nodes[index_of[j]] = node;
  }
  for (int k = 0, t = 0; k < top_triangles; ++k) {
    for (; t < int(count) && subtrees[t].triangle_position <= k; ++t) {
    }
    out.triangles[k + triangle_shift[t]] = top.triangles[k];
    out.triangle_ids[k + triangle_shift[t]] = top.triangle_ids[k];
  }
  for_each_index_cpu(
      count,
      [&](std::size_t t) {
        const WideSubtree& subtree = subtrees[t];
        const Fragment& f = subtree.fragment;
        for (std::size_t k = 0; k < f.nodes.size(); ++k) {
          SlotNode node = f.nodes[k];
          node.child_base += subtree.start - 1; // the fragment's node 1 is the subtree's start
          node.triangle_base += subtree.triangle_start;
          out.nodes[k == 0 ? index_of[subtree.node] : subtree.start + k - 1] = node;
        }
        std::copy(f.triangles.begin(), f.triangles.end(),
                  out.triangles.begin() + subtree.triangle_start);
        std::copy(f.triangle_ids.begin(), f.triangle_ids.end(),
                  out.triangle_ids.begin() + subtree.triangle_start);
      },
      threads, "parts");
}

// The layout's stats, from its nodes, in the order the serial layout visits them (depth first,
// a node's leaves before its own cost): the SAH cost is a sum of doubles, and a sum taken in
// another order may round to another last bit.
void layout_stats(const WideLayout& layout, double root_area, WideStats& stats) {
  double sah = 0.0; // unnormalised: areas, not area ratios
  long long children = 0;
  const auto visit = [&](const auto& self, int i, int depth) -> void {
    const SlotNode& node = layout.nodes[i];
    stats.depth = std::max(stats.depth, depth);
    for (int s = 0; s < k_slots; ++s) {
      if (node.meta[s] == 0) continue;
      ++children;
      if (is_interior_meta(node.meta[s])) continue;
      ++stats.leaves;
      sah += ch07::half_area_of(node.child_box[s]) *
             std::popcount(unsigned(node.meta[s]) >> 5) * k_triangle_cost;
    }
    sah += ch07::half_area_of(node.box) * k_node_cost;
    int child = node.child_base;
    for (int s = 0; s < k_slots; ++s)
      if (node.imask & (1u << s)) self(self, child++, depth + 1);
  };
  visit(visit, 0, 0);
  stats.references = static_cast<long long>(layout.triangles.size());
  stats.nodes = static_cast<int>(layout.nodes.size());
  stats.children_per_node = double(children) / double(stats.nodes);
  stats.triangles_per_leaf =
      double(layout.triangles.size()) / double(std::max(1, stats.leaves));
  stats.sah_cost = root_area > 0.0 ? sah / root_area : sah;
}

// The layout from the root's children: on one thread, or for a mesh too small to share (as in
// chapter 07's build), all of it depth first; on several, the top depth first with the subtrees
// of at most `handoff` references handed out, then the subtrees, each by one thread into a
// fragment of its own, then the splice.
template <class ChildrenOf>
void lay_out(const BinaryTree& tree, const Picks& root_picks, ChildrenOf children_of,
             int threads, WideLayout& out) {
  Fragment top;
  top.nodes.push_back(out.nodes[0]);
  const int references = static_cast<int>(tree.triangle_ids().size());
  if (threads == 1 || references < 2 * k_min_piece) {
    top.reserve(references);
    Layout(tree, children_of, top).emit(0, root_picks, 0);
    out.nodes = std::move(top.nodes);
    out.triangles = std::move(top.triangles);
    out.triangle_ids = std::move(top.triangle_ids);
    return;
  }
  const int handoff = std::max(k_min_piece, references / (k_pieces_per_thread * threads));
  std::vector<WideSubtree> subtrees;
  Layout top_layout(tree, children_of, top, handoff, &subtrees);
  top_layout.emit(0, root_picks, 0);
  std::vector<int> order(subtrees.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return tree.count(subtrees[a].edge) > tree.count(subtrees[b].edge);
  });
  for_each_index_cpu(
      order.size(),
      [&](std::size_t k) {
        WideSubtree& subtree = subtrees[order[k]];
        Fragment& f = subtree.fragment;
        f.reserve(tree.count(subtree.edge));
        f.nodes.push_back(top.nodes[subtree.node]);
        Layout(tree, children_of, f)
            .emit(0, children_of(tree.child_node(subtree.edge)), subtree.depth);
      },
      threads, "parts");
  splice(top, subtrees, top_layout.subtrees_before(), threads, out);
}

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
  out.threads = binary.options.threads > 0 ? binary.options.threads : cpu_thread_count();
  out.stats.split = binary.options.method;
  out.stats.triangles = binary.stats.triangles;
  // The first binary leaf too large, in leaf order (its references come first).
  int too_large = -1, too_large_first = 0;
  for (const ch07::BvhNode& node : binary.nodes)
    for (int c = 0; c < 2; ++c)
      if (node.is_leaf(c) && node.count[c] > k_max_leaf_triangles &&
          (too_large < 0 || node.first[c] < too_large_first)) {
        too_large = node.count[c];
        too_large_first = node.first[c];
      }
  if (too_large >= 0)
    throw InputError("collapse: a binary leaf of " + std::to_string(too_large) +
                     " triangles; a wide leaf holds at most " +
                     std::to_string(k_max_leaf_triangles));
  if (binary.nodes.empty()) return out;

  SlotNode root;
  root.box = binary.bounds;
  out.nodes.push_back(root);
  BinaryTree tree(binary);
  const ch07::BvhNode& top = binary.nodes[0];
  // The whole mesh in one leaf: chapter 07 stores a root whose child 0 is that leaf and whose
  // child 1 is empty (no triangles, no node: first -1). A child 1 of no triangles with a node
  // number is an interior child, beside a leaf child 0.
  if (top.is_leaf(0) && top.count[1] == 0 && top.first[1] < 0) { // a root with that leaf alone
    Picks alone;
    alone.push({BinaryTree::edge(0, 0), true});
    lay_out(
        tree, alone, [](int) { return Picks{}; }, 1, out);
  } else if (method == Collapse::sah) {
    const SahCollapse sah(tree, width, out.threads);
    const auto children_of = [&](int n) { return sah.children(n); };
    lay_out(tree, children_of(0), children_of, out.threads, out);
  } else {
    visit_bottom_up(plan_bottom_up(tree, out.threads), out.threads,
                    [&](int n, int) { tree.set_range(n); });
    const auto children_of = [&](int n) { return greedy_children(tree, n, width); };
    lay_out(tree, children_of(0), children_of, out.threads, out);
  }
  layout_stats(out, ch07::half_area_of(binary.bounds), out.stats);
  out.stats.build_ms =
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
