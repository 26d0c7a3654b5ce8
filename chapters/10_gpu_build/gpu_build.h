// Chapter 10: trees built in parallel, on the GPU or on CPU threads through the same RT_HD
// passes: the LBVH (Morton codes, a sort, Karras's hierarchy, boxes from the bottom up) and the
// refit of an existing tree to moved vertices. Both end in chapter 07's layout (bvh.h), so
// chapter 07's checker, traversal and runner, and chapter 09's collapse, take them unchanged.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "bvh.h"
#include "mesh_gen.h"
#include "morton.h"
#include "rt/backend.h"
#include "tree_arrays.h"

namespace rt::ch10 {

// A tree built by this chapter, with what the report says about its build.
struct GpuBuild {
  ch07::Bvh bvh;         // chapter 07's layout, depth first, stats filled
  double build_ms = 0.0; // GPU: kernel time with CUDA events, the sort included; CPU: wall
  CodeWidth codes = CodeWidth::bits30; // the codes the tree was built from
  std::string note;                    // what the build had to do differently, if anything
  int rounds = 0;          // PLOC: its clustering rounds (at most ploc_round_bound); else 0
  int rounds_in_order = 0; // PLOC: those of them that paired the clusters in place order
};

// The LBVH of `mesh` on the resolved backend: one triangle per leaf, laid out depth first.
// Both backends give the same tree bit for bit. A tree of 63-bit codes deeper than chapter 07's
// traversal stack allows is built again from 30-bit codes, whose trees never are (gpu_build.cu
// proves it); GpuBuild::note says so. Throws InputError as ch07::check_build_input does, and
// when the GPU lacks the memory for the build.
GpuBuild build_lbvh(Backend backend, const ch04::Mesh& mesh, CodeWidth codes);

// The LBVH of 30-bit codes of a mesh that stays where the backend reads it (backend
// pointers; at least two triangles; its vertices may move between builds): the arrays are made
// once, and each build() runs the passes alone, its tree left on the backend (on the GPU,
// queued and not waited for). The tree is build_lbvh's for the same mesh.
class LbvhOnBackend {
public:
  LbvhOnBackend(Backend backend, ch04::MeshView mesh);
  ~LbvhOnBackend();
  void build();
  TreeArrays& tree();

private:
  struct Passes;
  std::unique_ptr<Passes> passes_;
};

// An LBVH over boxes, copied to the host: node_count nodes in chapter 07's layout, root 0, and
// the box in each leaf slot. A leaf is a child with count 1 whose `first` is its slot k; slot
// k holds box leaf_ids[k].
struct BoxTree {
  std::vector<ch07::BvhNode> nodes;
  std::vector<int> leaf_ids;
};

// The LBVH of boxes that stay where the backend reads them (chapter 13's world boxes of its
// instances, rewritten every frame): 30-bit Morton codes of the box centroids within the
// centroids' bounds, chapter 10's hierarchy and depth-first layout, one box per leaf, node
// boxes from the bottom up from the leaf boxes themselves. The same passes as build_lbvh, so
// over the boxes of a mesh's triangles it makes build_lbvh's 30-bit tree, and both backends
// make the same tree bit for bit; gpu_build.cu's depth proof holds for it (30-bit codes, at
// most 2^28 boxes), so its depth is never checked. The caller guarantees finite, non-empty
// boxes (build() does not look). One box: chapter 07's one-leaf root, child 1 empty; none: no
// nodes.
class LbvhOverBoxes {
public:
  // Every array for up to `capacity` boxes, CUB's scratch included, made here and only here.
  LbvhOverBoxes(Backend backend, int capacity);
  ~LbvhOverBoxes();
  LbvhOverBoxes(LbvhOverBoxes&&) noexcept;
  LbvhOverBoxes& operator=(LbvhOverBoxes&&) noexcept;

  // The tree of boxes[0 .. count-1] (backend pointers, kept in place until the build has run).
  // On the GPU no allocation and no wait: the passes are queued on the default stream, and
  // whatever reads the tree there later sees it (on CPU threads the passes run before it
  // returns, and std::stable_sort takes a buffer of its own). Throws UsageError for a count
  // above capacity.
  void build(const ch07::Aabb* boxes, int count);

  const ch07::BvhNode* nodes() const; // backend pointer: node_count() nodes, root 0
  const int* leaf_ids() const;        // backend pointer: count() entries, slot k's box number
  const int* parents() const; // backend pointer: each node's 2 * parent + slot; -1 at the root
  int node_count() const;     // count() - 1; 1 for a single box; 0 for none
  int count() const;          // the boxes of the last build
  int capacity() const;
  BoxTree to_host() const; // the last build's tree copied to the host (on the GPU, a wait)

private:
  struct Passes;
  std::unique_ptr<Passes> passes_;
};

// The LBVH over `boxes` on the resolved backend, copied to the host: LbvhOverBoxes made for
// them, built once. Throws InputError naming the first box that is empty or not finite.
BoxTree build_lbvh_over_boxes(Backend backend, std::span<const ch07::Aabb> boxes);

// PLOC's search radius: each cluster looks for its nearest neighbour among this many clusters
// on either side of it in Morton order.
inline constexpr int k_ploc_radius = 8;

// A PLOC round whose mutual pairs are fewer than one in this many of its clusters pairs all
// of them in place order instead (the first with the second, ...), so that every round
// removes a fixed share of the clusters, whatever the input.
inline constexpr int k_ploc_ordered_share = 32;

// The most rounds PLOC takes for n triangles, whatever they are (ploc.cu proves it): about
// F ln(n / F) + F for F = k_ploc_ordered_share; 293 for 200 000 triangles.
int ploc_round_bound(long long n);

// PLOC (Meister & Bittner 2018) on the resolved backend: the triangles in 30-bit Morton order
// are clusters; every cluster finds the neighbour within `radius` whose merged box has the
// smallest surface area, pairs that chose each other merge (in a round where they are too
// few, all clusters pair in place order instead), and the rounds go on until one cluster is
// left. One triangle per leaf, laid out depth first; both backends give the same tree bit for
// bit. A tree deeper than chapter 07's stack allows is replaced by the 30-bit LBVH
// (GpuBuild::note says so; its rounds are PLOC's). Throws InputError as build_lbvh does, and
// for a radius outside 1..64.
GpuBuild build_ploc(Backend backend, const ch04::Mesh& mesh, int radius = k_ploc_radius);

// A warp's lanes, and the most clusters an H-PLOC subtree passes up: half a warp, so that the
// lists of a node's two children, side by side, fill at most one warp.
inline constexpr int k_warp_lanes = 32;
inline constexpr int k_hploc_threshold = k_warp_lanes / 2;

// H-PLOC (Benthin, Meister, Barczak, Parker & Wald 2024) on the resolved backend: one walk up
// the 30-bit LBVH's hierarchy in which every subtree passes up a list of clusters instead of
// one node; where a list would grow past `threshold` (at most k_hploc_threshold), and at
// the root, PLOC's merges (nearest neighbour within `radius`, mutual pairs, the leftmost of
// equal ones) run inside it until `threshold` clusters are left (one at the root). One
// triangle per leaf, laid out depth first; both backends give the same tree bit for bit. A
// threshold of 1 merges every node's two clusters as they come: the LBVH itself. A tree
// deeper than chapter 07's stack allows is replaced by the 30-bit LBVH (GpuBuild::note says
// so). `treelet_rounds` rounds of treelet restructuring (treelets.h) then improve the tree
// before it is laid out. Throws InputError as build_lbvh does, and for a radius outside
// 1..31, a threshold outside 1..16 or rounds outside 0..k_max_treelet_rounds.
inline constexpr int k_max_treelet_rounds = 8;
inline constexpr int k_treelet_rounds = 3; // the rounds of the builder "H-PLOC + treelets"
GpuBuild build_hploc(Backend backend, const ch04::Mesh& mesh, int radius = k_ploc_radius,
                     int threshold = k_hploc_threshold, int treelet_rounds = 0);

// New boxes for the same tree after the mesh's vertices moved (same triangles, same vertex
// count): the triangle copies are taken again from `mesh`, every box is recomputed from the
// bottom up, and bounds and the SAH cost follow. Any tree in chapter 07's layout that passes
// its checker for the mesh it was built from (the refit trusts its indices). Returns the
// time taken, as build_ms is measured. Throws InputError as ch07::check_build_input does, and
// when the mesh has another triangle count than the tree.
double refit_bvh(Backend backend, ch07::Bvh& bvh, const ch04::Mesh& mesh);

// The report's figures for a tree in chapter 07's layout, filled from the tree itself: nodes,
// leaves, depth, leaf sizes, SAH cost and bytes per triangle (chapter 07's stats, computed as
// its build computes them).
void fill_stats(ch07::Bvh& bvh);

} // namespace rt::ch10
