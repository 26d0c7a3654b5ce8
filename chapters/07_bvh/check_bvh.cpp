// Chapter 07: the tree checker. See check_bvh.h.
#include "check_bvh.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "bvh_build.h"
#include "rt/error.h"
#include "sbvh_build.h"

namespace rt::ch07 {
namespace {

// Problems found by check_bvh, as lines. A badly broken tree can have millions; the first few
// say what is wrong, the rest are only counted.
class Problems {
public:
  void add(const std::string& line) {
    if (lines_.size() < k_shown) {
      lines_.push_back(line);
    } else {
      ++hidden_;
    }
  }
  std::vector<std::string> finish() {
    if (hidden_ > 0) lines_.push_back("... and " + std::to_string(hidden_) + " more problems");
    return std::move(lines_);
  }

private:
  static constexpr std::size_t k_shown = 50;
  std::vector<std::string> lines_;
  long long hidden_ = 0;
};

std::string child_name(int node, int child) {
  return "node " + std::to_string(node) + " child " + std::to_string(child);
}

bool same_bits(const Aabb& a, const Aabb& b) { return std::memcmp(&a, &b, sizeof(Aabb)) == 0; }

bool nearly_equal(double a, double b) {
  return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b));
}

// One check of one tree: the walk from the root as the traversal makes it, marking what it
// reaches, then what it never reached, then the stats against what it counted.
class Checker {
public:
  Checker(const Bvh& bvh, const ch04::Mesh& mesh)
      : bvh_(bvh), mesh_(mesh), n_(static_cast<long long>(mesh.triangles.size())),
        slot_count_(static_cast<long long>(bvh.triangles.size())),
        node_count_(static_cast<long long>(bvh.nodes.size())) {}

  std::vector<std::string> run() {
    check_sizes();
    walk();
    check_reached();
    check_stats();
    return problems_.finish();
  }

private:
  struct Entry {
    int node, depth;
  };

  void check_sizes() {
    max_leaf_ = bvh_.options.max_leaf_size;
    try {
      check_build_options(bvh_.options);
    } catch (const InputError& error) {
      problems_.add(std::string("options: ") + error.what());
      max_leaf_ = k_max_leaf_size;
    }
    // Spatial splits reference a triangle from several leaves, within the budget; the other
    // builds copy each triangle exactly once.
    spatial_ = bvh_.options.method == SplitMethod::sbvh;
    const long long most =
        spatial_ ? n_ + static_cast<long long>(
                            std::floor(bvh_.options.split_budget * static_cast<double>(n_)))
                 : n_;
    if (slot_count_ < n_ || slot_count_ > most)
      problems_.add(std::to_string(slot_count_) + " triangle copies for " + std::to_string(n_) +
                    " mesh triangles" + (spatial_ ? " (more than the budget allows)" : ""));
    if (static_cast<long long>(bvh_.triangle_ids.size()) != slot_count_)
      problems_.add(std::to_string(bvh_.triangle_ids.size()) + " triangle ids for " +
                    std::to_string(slot_count_) + " triangle copies");
    if (n_ == 0 && node_count_ != 0)
      problems_.add("a mesh with no triangles must give no nodes");
    if (n_ > 0 && node_count_ == 0)
      problems_.add("no nodes for " + std::to_string(n_) + " triangles");
  }

  void walk() {
    node_reached_.assign(node_count_, 0);
    slot_uses_.assign(slot_count_, 0);
    id_uses_.assign(n_, 0);
    counted_.leaf_sizes.assign(max_leaf_ + 1, 0);
    if (node_count_ > 0) {
      node_reached_[0] = 1;
      stack_.push_back({0, 0});
    }
    while (!stack_.empty()) {
      const auto [i, depth] = stack_.back();
      stack_.pop_back();
      const BvhNode& node = bvh_.nodes[i];
      ++counted_.nodes;
      counted_.depth = std::max(counted_.depth, depth);
      if (depth > k_max_bvh_depth - 1)
        problems_.add("node " + std::to_string(i) + " is at depth " + std::to_string(depth) +
                      ", deeper than " + std::to_string(k_max_bvh_depth - 1));
      for (int c = 0; c < 2; ++c) {
        if (node.count[c] < 0) {
          problems_.add(child_name(i, c) + " has count " + std::to_string(node.count[c]));
        } else if (node.count[c] > 0) {
          check_leaf(i, c);
        } else if (node.first[c] == -1 && i == 0 && c == 1 && node.count[0] > 0) {
          // The empty child of a root whose whole mesh is one leaf.
          if (!same_bits(node.box[c], Aabb{}))
            problems_.add("node 0 child 1 is empty but has a box");
        } else {
          check_interior(i, c, depth);
        }
      }
    }
  }

  void check_leaf(int i, int c) {
    const BvhNode& node = bvh_.nodes[i];
    const int first = node.first[c], count = node.count[c];
    ++counted_.leaves;
    if (count > max_leaf_) {
      problems_.add(child_name(i, c) + " is a leaf of " + std::to_string(count) +
                    " triangles, more than " + std::to_string(max_leaf_));
    } else {
      ++counted_.leaf_sizes[count];
    }
    if (first < 0 || static_cast<long long>(first) + count > slot_count_) {
      problems_.add(child_name(i, c) + " names triangles " + std::to_string(first) + ".." +
                    std::to_string(static_cast<long long>(first) + count - 1) + " of " +
                    std::to_string(slot_count_));
      return;
    }
    for (int k = first; k < first + count; ++k) {
      if (slot_uses_[k]++ == 1)
        problems_.add("triangle copy " + std::to_string(k) + " is in two leaves");
      // A spatial split's leaf holds only the part of a triangle inside its box: the box must
      // meet the triangle's (that it holds the whole part is the clip's promise, tested apart).
      const Aabb own = bounds_of(bvh_.triangles[k]);
      if (spatial_ ? intersection_of(node.box[c], own).empty() : !node.box[c].contains(own))
        problems_.add(child_name(i, c) + ": box does not " + (spatial_ ? "meet" : "contain") +
                      " triangle copy " + std::to_string(k));
      if (k < static_cast<long long>(bvh_.triangle_ids.size())) check_triangle_copy(k);
    }
    // No triangle twice in one leaf: the traversal would test it twice for nothing.
    for (int k = first;
         k < first + count && k < static_cast<long long>(bvh_.triangle_ids.size()); ++k)
      for (int j = first; j < k; ++j)
        if (bvh_.triangle_ids[j] == bvh_.triangle_ids[k])
          problems_.add(child_name(i, c) + " holds mesh triangle " +
                        std::to_string(bvh_.triangle_ids[k]) + " twice");
  }

  void check_triangle_copy(int k) {
    const int id = bvh_.triangle_ids[k];
    if (id < 0 || id >= n_) {
      problems_.add("triangle copy " + std::to_string(k) + " has id " + std::to_string(id) +
                    ", not a mesh triangle");
      return;
    }
    if (id_uses_[id]++ == 1 && !spatial_)
      problems_.add("mesh triangle " + std::to_string(id) + " is in two leaves");
    const TriangleF original = mesh_.triangle(id);
    if (std::memcmp(&original, &bvh_.triangles[k], sizeof(TriangleF)) != 0)
      problems_.add("triangle copy " + std::to_string(k) + " differs from mesh triangle " +
                    std::to_string(id));
  }

  void check_interior(int i, int c, int depth) {
    const int first = bvh_.nodes[i].first[c];
    if (c == 0 && first != i + 1)
      problems_.add(child_name(i, c) + " is node " + std::to_string(first) +
                    ", not the next node " + std::to_string(i + 1));
    if (!(first > i && first < node_count_)) {
      problems_.add(child_name(i, c) + " is node " + std::to_string(first) + ", outside (" +
                    std::to_string(i) + ", " + std::to_string(node_count_) + ")");
      return;
    }
    if (node_reached_[first]) {
      problems_.add("node " + std::to_string(first) + " is reached twice");
      return;
    }
    node_reached_[first] = 1;
    const BvhNode& child = bvh_.nodes[first];
    for (int g = 0; g < 2; ++g)
      if (!bvh_.nodes[i].box[c].contains(child.box[g]))
        problems_.add(child_name(i, c) + ": box does not contain the box of " +
                      child_name(first, g));
    stack_.push_back({first, depth + 1});
  }

  void check_reached() {
    long long unreached = 0, unused = 0, missing = 0;
    for (long long i = 0; i < node_count_; ++i) unreached += node_reached_[i] == 0;
    if (unreached > 0) problems_.add(std::to_string(unreached) + " nodes are never reached");
    for (long long k = 0; k < slot_count_; ++k) unused += slot_uses_[k] == 0;
    if (unused > 0) problems_.add(std::to_string(unused) + " triangle copies are in no leaf");
    for (long long id = 0; id < n_; ++id) missing += id_uses_[id] == 0;
    if (missing > 0) problems_.add(std::to_string(missing) + " mesh triangles are in no leaf");
    for (int c = 0; c < 2 && node_count_ > 0; ++c)
      if (!bvh_.bounds.contains(bvh_.nodes[0].box[c])) // an empty box is inside any box
        problems_.add("the bounds do not contain the box of " + child_name(0, c));
  }

  void check_stats() {
    const BuildStats& stats = bvh_.stats;
    const auto mismatch = [&](const char* what, const std::string& stored,
                              const std::string& tree) {
      problems_.add(std::string("stats.") + what + " is " + stored + ", the tree has " + tree);
    };
    if (stats.nodes != counted_.nodes)
      mismatch("nodes", std::to_string(stats.nodes), std::to_string(counted_.nodes));
    if (stats.leaves != counted_.leaves)
      mismatch("leaves", std::to_string(stats.leaves), std::to_string(counted_.leaves));
    if (stats.depth != counted_.depth)
      mismatch("depth", std::to_string(stats.depth), std::to_string(counted_.depth));
    if (stats.leaf_sizes != counted_.leaf_sizes)
      mismatch("leaf_sizes", "a different histogram", "these leaves");
    if (!nearly_equal(stats.sah_cost, sah_cost(bvh_)))
      mismatch("sah_cost", std::to_string(stats.sah_cost), std::to_string(sah_cost(bvh_)));
    const double bytes =
        n_ > 0 ? (static_cast<double>(node_count_) * sizeof(BvhNode) +
                  static_cast<double>(slot_count_) * (sizeof(TriangleF) + sizeof(int))) /
                     static_cast<double>(n_)
               : 0.0;
    if (!nearly_equal(stats.bytes_per_triangle, bytes))
      mismatch("bytes_per_triangle", std::to_string(stats.bytes_per_triangle),
               std::to_string(bytes));
  }

  const Bvh& bvh_;
  const ch04::Mesh& mesh_;
  const long long n_, slot_count_, node_count_;
  int max_leaf_ = 0;
  bool spatial_ = false; // an sbvh tree: a triangle may be in several leaves
  Problems problems_;
  BuildStats counted_;
  std::vector<unsigned char> node_reached_;
  std::vector<int> slot_uses_, id_uses_;
  std::vector<Entry> stack_;
};

} // namespace

std::vector<std::string> check_bvh(const Bvh& bvh, const ch04::Mesh& mesh) {
  return Checker(bvh, mesh).run();
}

} // namespace rt::ch07
