// Chapter 09: the checker of a stored wide tree, read the way the traversal reads it. See
// collapse.h.
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "collapse.h"
#include "sbvh_build.h"

namespace rt::ch09 {
namespace {

// The first problems as lines, the rest counted (as chapter 07's checker does).
class Problems {
public:
  void add(const std::string& line) {
    if (lines_.size() < 50)
      lines_.push_back(line);
    else
      ++hidden_;
  }
  std::vector<std::string> finish() {
    if (hidden_ > 0) lines_.push_back("... and " + std::to_string(hidden_) + " more problems");
    return std::move(lines_);
  }

private:
  std::vector<std::string> lines_;
  long long hidden_ = 0;
};

template <class Node, class Triangles> class Checker {
public:
  Checker(const WideTree<Node, Triangles>& tree, const ch04::Mesh& mesh,
          const ch07::BuildOptions& binary, Problems& problems)
      : tree_(tree.view()), mesh_(mesh), problems_(problems),
        spatial_(binary.method == ch07::SplitMethod::sbvh), reached_(tree.nodes.size(), 0),
        record_uses_(tree.triangles.size() / Triangles::k_records, 0),
        id_uses_(mesh.triangles.size(), 0) {
    // Spatial splits reference a triangle from several leaves, within the budget chapter 07's
    // checker allows; the other builds store each triangle exactly once.
    const long long n = static_cast<long long>(mesh.triangles.size());
    const long long most =
        spatial_ ? n + static_cast<long long>(std::floor(binary.split_budget * double(n))) : n;
    const long long records = static_cast<long long>(record_uses_.size());
    if (tree.triangles.size() % Triangles::k_records != 0 || records < n || records > most)
      problems_.add(std::to_string(tree.triangles.size()) + " triangle records for " +
                    std::to_string(n) + " mesh triangles" +
                    (spatial_ ? " (more than the split budget allows)" : ""));
  }

  void run() {
    const long long n = static_cast<long long>(mesh_.triangles.size());
    if ((n == 0) != (tree_.node_count == 0))
      problems_.add(std::to_string(tree_.node_count) + " nodes for " + std::to_string(n) +
                    " triangles");
    if (tree_.node_count > 0) {
      reached_[0] = 1;
      constexpr float inf = std::numeric_limits<float>::infinity();
      visit(0, 0, Aabb{{-inf, -inf, -inf}, {inf, inf, inf}}); // the root's box is not tested
    }
    long long unreached = 0, unused = 0, missing = 0;
    for (const unsigned char r : reached_) unreached += r == 0;
    for (const int u : record_uses_) unused += u == 0;
    for (const int u : id_uses_) missing += u == 0;
    if (unreached > 0) problems_.add(std::to_string(unreached) + " nodes are never reached");
    if (unused > 0) problems_.add(std::to_string(unused) + " triangle records are in no leaf");
    if (missing > 0) problems_.add(std::to_string(missing) + " mesh triangles are in no leaf");
  }

private:
  std::string name(int node, int c) const {
    return "node " + std::to_string(node) + " child " + std::to_string(c);
  }

  // The exact bounds of the triangles below `index`, checking its children on the way; for an
  // sbvh tree, of the parts of them inside `reach`, the boxes a ray passed on its way here.
  Aabb visit(int index, int depth, const Aabb& reach) {
    if (depth > k_wide_stack_size)
      problems_.add("node " + std::to_string(index) + " is at depth " + std::to_string(depth) +
                    ", beyond the stack's bound " + std::to_string(k_wide_stack_size));
    const Node node = tree_.nodes[index];
    Aabb exact_bounds;
    int children = 0, interior = 0;
    unsigned slots_seen = 0, triangle_bits = 0;
    for (int c = 0; c < Node::k_width; ++c) {
      const std::uint8_t meta = node.meta[c];
      if (meta == 0) continue;
      ++children;
      Aabb exact;
      if (is_interior_meta(meta)) {
        if ((meta >> 5) != 1) problems_.add(name(index, c) + ": interior meta with a count");
        const unsigned slot = meta & 7u;
        if (slots_seen & (1u << slot)) problems_.add(name(index, c) + ": its slot twice");
        slots_seen |= 1u << slot;
        if (!(node.imask & (1u << slot))) {
          problems_.add(name(index, c) + " is interior but imask lacks slot " +
                        std::to_string(slot));
          continue;
        }
        ++interior;
        const int child =
            node.child_base + std::popcount(unsigned(node.imask) & ((1u << slot) - 1u));
        if (child <= index || child >= tree_.node_count) {
          problems_.add(name(index, c) + " is node " + std::to_string(child) + ", outside (" +
                        std::to_string(index) + ", " + std::to_string(tree_.node_count) + ")");
          continue;
        }
        if (reached_[child]) {
          problems_.add("node " + std::to_string(child) + " is reached twice");
          continue;
        }
        reached_[child] = 1;
        exact = visit(child, depth + 1, ch07::intersection_of(reach, child_box_of(node, c)));
      } else {
        const unsigned count_bits = meta >> 5, offset = meta & 31u;
        const int count = count_bits == 1 ? 1 : count_bits == 3 ? 2 : count_bits == 7 ? 3 : 0;
        if (count == 0 || offset + count > unsigned(k_triangle_bits)) {
          problems_.add(name(index, c) + ": leaf meta " + std::to_string(meta) + " is invalid");
          continue;
        }
        const unsigned bits = count_bits << offset;
        if (triangle_bits & bits) problems_.add(name(index, c) + ": its triangles overlap");
        triangle_bits |= bits;
        const int first = node.triangle_base + int(offset);
        for (int k = first; k < first + count; ++k) {
          const Aabb own = check_record(k, index, c);
          if (!spatial_) {
            exact.grow(own);
            continue;
          }
          // Chapter 07's rule for a spatial split's leaf: it holds only the part of its
          // triangle inside its box, so the box must meet the triangle's, here together with
          // every box above it (a ray reaches the leaf only through all of them).
          const Aabb part =
              ch07::intersection_of(ch07::intersection_of(reach, child_box_of(node, c)), own);
          if (part.empty() && !own.empty())
            problems_.add(name(index, c) +
                          ": the boxes on its way do not meet triangle record " +
                          std::to_string(k));
          exact.grow(part);
        }
        check_once_in_leaf(first, count, index, c);
      }
      if (!child_box_of(node, c).contains(exact))
        problems_.add(name(index, c) + ": its box does not contain the triangles below it");
      exact_bounds.grow(exact);
    }
    if (bit_count_of(node.imask) != interior)
      problems_.add("node " + std::to_string(index) + ": imask names " +
                    std::to_string(bit_count_of(node.imask)) + " interior children, it has " +
                    std::to_string(interior));
    const bool one_leaf_root = index == 0 && children == 1 && interior == 0;
    if (children < 2 && !one_leaf_root)
      problems_.add("node " + std::to_string(index) + " has " + std::to_string(children) +
                    " children");
    return exact_bounds;
  }

  static int bit_count_of(unsigned x) { return std::popcount(x); }

  // No mesh triangle twice in one leaf: the traversal would test it twice for nothing.
  void check_once_in_leaf(int first, int count, int node, int c) {
    if (first < 0 || first + count > static_cast<int>(record_uses_.size())) return;
    for (int k = first + 1; k < first + count; ++k)
      for (int j = first; j < k; ++j)
        if (tree_.triangle_id(j) == tree_.triangle_id(k))
          problems_.add(name(node, c) + " holds mesh triangle " +
                        std::to_string(tree_.triangle_id(k)) + " twice");
  }

  // Triangle record k: in one leaf only, a mesh triangle's id, that triangle bit for bit.
  Aabb check_record(int k, int node, int c) {
    Aabb box;
    if (k < 0 || k >= static_cast<int>(record_uses_.size())) {
      problems_.add(name(node, c) + " names triangle record " + std::to_string(k));
      return box;
    }
    if (record_uses_[k]++ == 1)
      problems_.add("triangle record " + std::to_string(k) + " is in two leaves");
    const TriangleF t = tree_.triangle(k);
    box.grow(t.v0);
    box.grow(t.v1);
    box.grow(t.v2);
    const int id = tree_.triangle_id(k);
    if (id < 0 || id >= static_cast<int>(id_uses_.size())) {
      problems_.add("triangle record " + std::to_string(k) + " has id " + std::to_string(id));
      return box;
    }
    if (id_uses_[id]++ == 1 && !spatial_)
      problems_.add("mesh triangle " + std::to_string(id) + " is in two leaves");
    const TriangleF original = mesh_.triangle(id);
    if (std::memcmp(&original, &t, sizeof t) != 0)
      problems_.add("triangle record " + std::to_string(k) + " differs from mesh triangle " +
                    std::to_string(id));
    return box;
  }

  const WideTreeView<Node, Triangles> tree_;
  const ch04::Mesh& mesh_;
  Problems& problems_;
  const bool spatial_; // from an sbvh tree: a triangle may be in several leaves
  std::vector<unsigned char> reached_;
  std::vector<int> record_uses_, id_uses_;
};

} // namespace

template <class Node, class Triangles>
std::vector<std::string> check_wide_tree(const WideTree<Node, Triangles>& tree,
                                         const ch04::Mesh& mesh,
                                         const ch07::BuildOptions& binary) {
  Problems problems;
  Checker<Node, Triangles>(tree, mesh, binary, problems).run();
  return problems.finish();
}

template std::vector<std::string> check_wide_tree(const Wide4Bvh&, const ch04::Mesh&,
                                                  const ch07::BuildOptions&);
template std::vector<std::string> check_wide_tree(const Wide8Bvh&, const ch04::Mesh&,
                                                  const ch07::BuildOptions&);
template std::vector<std::string> check_wide_tree(const CompressedBvh&, const ch04::Mesh&,
                                                  const ch07::BuildOptions&);
template std::vector<std::string> check_wide_tree(const Wide4PackedBvh&, const ch04::Mesh&,
                                                  const ch07::BuildOptions&);

} // namespace rt::ch09
