// Chapter 07: building the BVH on the CPU, two ways. The object median is the textbook
// baseline; the binned surface area heuristic (Wald 2007) is what every fast tracer uses. Both
// end in the same flat, depth-first node array that bvh.h describes, and both obey a depth
// bound that is proved, not hoped for, so the traversal's fixed-size stack cannot overflow.
#pragma once

#include <string>
#include <vector>

#include "bvh.h"
#include "mesh_gen.h"

namespace rt::ch07 {

// The most triangles a BVH holds. Node and triangle numbers are ints, and the depth bound
// below needs the root to fit: halving 1 << 28 triangles down to leaves of one takes 28 levels.
inline constexpr long long k_max_bvh_triangles = 1LL << 28;

// How many levels of interior nodes a build that halves every node (an object-median split)
// needs before every piece fits in a leaf of `max_leaf_size`: 0 if m <= max_leaf_size, else
// 1 + halving_levels(ceil(m / 2)). The depth bound of the build rests on this count.
constexpr int halving_levels(long long triangle_count, int max_leaf_size) {
  int levels = 0;
  for (long long m = triangle_count; m > max_leaf_size; m = (m + 1) / 2) ++levels;
  return levels;
}
static_assert(halving_levels(k_max_bvh_triangles, 1) <= k_max_bvh_depth - 1,
              "the largest mesh must fit under the depth bound even with leaves of one");

// The most split_budget accepts: (1 + 4) << 28 references still fit an int.
inline constexpr double k_max_split_budget = 4.0;

// The most threads a build takes (as many as the CPU backend ever uses).
inline constexpr int k_max_build_threads = 1024;

// Throws rt::InputError, one line naming the option, unless 1 <= max_leaf_size <=
// k_max_leaf_size, 2 <= bins <= 256, 0 <= split_budget <= k_max_split_budget and
// 0 <= threads <= k_max_build_threads.
void check_build_options(const BuildOptions& options);

// Throws rt::InputError for more than k_max_bvh_triangles triangles, and, naming the triangle,
// for a vertex index out of range or a vertex that is not finite (its box and centroid would
// be meaningless). Every builder of the course calls it first.
void check_build_input(const ch04::Mesh& mesh);

// Builds the tree over every triangle of `mesh`. Throws rt::InputError for bad options, for
// more than k_max_bvh_triangles triangles, and for a triangle with a vertex index out of range
// or a vertex that is not finite (the message names the triangle). A mesh with no triangles
// gives a tree with no nodes. Deterministic: the same mesh and options always give the same
// arrays, bit for bit, whatever options.threads is (median and sah build on that many threads,
// sbvh on one).
Bvh build_bvh(const ch04::Mesh& mesh, const BuildOptions& options);

// The surface area heuristic's cost of a finished tree: the expected number of node visits
// plus triangle tests of a ray that hits the root box, if rays were spread uniformly over
// directions and positions. A box is entered with probability A(box) / A(root) (A: surface
// area), so the cost is the sum over interior nodes of A(node) / A(root), plus the sum over
// leaves of A(leaf) / A(root) * n(leaf). A node's box is the union of its two child boxes,
// the root's is Bvh::bounds. Computed in double, so it stays finite for any float mesh.
double sah_cost(const Bvh& bvh);

} // namespace rt::ch07
