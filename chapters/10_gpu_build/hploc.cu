// Chapter 10: H-PLOC, hierarchical PLOC (Benthin, Meister, Barczak, Parker & Wald 2024). See
// gpu_build.h and hploc.h. PLOC's rounds each look at every cluster of the scene and end in a
// wait for the host; H-PLOC runs PLOC inside the LBVH's subtrees instead, during one walk up
// the hierarchy, so that all of it is one kernel: a thread per leaf climbs while it is the
// second to reach a node, and a warp merges the lists of clusters it meets on the way.
#include "gpu_build.h"

#include <algorithm>
#include <string>

#include "build_passes.cuh"
#include "bvh_build.h"
#include "hploc_walk.h"
#include "model_render.h"
#include "rt/error.h"
#include "treelets.h"

namespace rt::ch10 {
namespace {

using namespace passes;

// The start: every leaf a cluster of its own, boxed, in its own place; no node's far end
// known yet.
struct StartLeaves {
  ClusterTree tree;
  const Aabb* triangle_boxes;
  const int* sorted_ids;
  int* clusters;
  unsigned long long* far_ends;
  RT_HD void operator()(int k) const {
    tree.boxes[k] = triangle_boxes[sorted_ids[k]];
    tree.leaf_counts[k] = 1;
    tree.parents[k] = -1;
    clusters[k] = k;
    if (k < tree.n - 1) {
      far_ends[k] = k_no_far_end;
      tree.parents[tree.n + k] = -1;
    }
  }
};

#if RT_DEVICE_CODE_POSSIBLE
constexpr unsigned k_all_lanes = 0xffffffffu;
// Threads per block of the walk: eight warps. Of blocks of 32, 64, 128 and 256 threads, 256
// gave the shortest walk on the H200, 7 to 8 % shorter than 128 on the dragon and the
// conference room (book/data/10_hploc_h200_walk_blocks.txt).
constexpr int k_hploc_block = 256;

// The warp's collective operations for walk_on_warp (hploc_walk.h): CUDA's intrinsics over
// all 32 lanes.
struct DeviceWarp {
  __device__ unsigned ballot(bool p) const { return __ballot_sync(k_all_lanes, p); }
  __device__ bool any(bool p) const { return __any_sync(k_all_lanes, p) != 0; }
  __device__ int shfl(int v, int from) const { return __shfl_sync(k_all_lanes, v, from); }
  __device__ float shfl(float v, int from) const { return __shfl_sync(k_all_lanes, v, from); }
  __device__ float shfl_down(float v, int d) const {
    return __shfl_down_sync(k_all_lanes, v, d);
  }
  __device__ float shfl_up(float v, int d) const { return __shfl_up_sync(k_all_lanes, v, d); }
  __device__ void sync() const { __syncwarp(); }
  __device__ void publish() const {
    __syncwarp();
    __threadfence();
  }
};

// The whole walk in one kernel, a thread per leaf.
__global__ void hploc_kernel(HplocWalk walk) {
  DeviceWarp warp;
  walk_on_warp(warp, walk, static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x),
               static_cast<int>(threadIdx.x % k_warp_lanes));
}

// A round of treelet restructuring, the warp searching each treelet together (treelets.h).
__global__ void treelet_kernel(RestructureTreelets pass) {
  __shared__ TreeletTables tables[k_hploc_block / k_warp_lanes];
  DeviceWarp warp;
  restructure_on_warp(warp, pass, static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x),
                      static_cast<int>(threadIdx.x % k_warp_lanes),
                      tables[threadIdx.x / k_warp_lanes]);
}
#endif

void restructure_round(Backend backend, const RestructureTreelets& pass) {
  const int n = pass.tree.n;
  if (backend == Backend::cpu) {
    for_each_index(backend, n, pass);
    return;
  }
#if RT_DEVICE_CODE_POSSIBLE
  treelet_kernel<<<blocks_to_cover(n, k_hploc_block), k_hploc_block>>>(pass);
  RT_CUDA_CHECK_LAUNCH("treelet_kernel");
#endif
}

void walk_up(Backend backend, const HplocWalk& walk) {
  const int n = walk.tree.n;
  if (backend == Backend::cpu) {
    for_each_index_cpu(
        static_cast<std::size_t>(n), [&](std::size_t leaf) { walk_on_cpu(walk, int(leaf)); },
        cpu_thread_count(), "leaves");
    return;
  }
#if RT_DEVICE_CODE_POSSIBLE
  hploc_kernel<<<blocks_to_cover(n, k_hploc_block), k_hploc_block>>>(walk);
  RT_CUDA_CHECK_LAUNCH("hploc_kernel");
#endif
}

// Interior node j's place in chapter 07's arrays and the slot of its first leaf, counted on
// the way up as PLOC's are (ploc.cu), and the node at each place. Only interior nodes walk: a
// leaf's slot follows from its parent's first slot (WriteClusters), and a leaf may sit one
// level below the deepest interior node allowed, so the interior nodes' depth check is the
// whole tree's.
struct PlaceClusters {
  ClusterTree tree;
  int* index;      // of each interior node
  int* first_slot; // of each interior node's first leaf
  int* node_at;    // of each place in chapter 07's array: the interior node there
  int* too_deep;
  RT_HD void operator()(int j) const {
    const WayUp up = place_on_way_up(tree, tree.n + j, ch07::k_max_bvh_depth - 1);
    if (up.too_deep) {
      mark(too_deep);
      return;
    }
    index[j] = up.index;
    first_slot[j] = up.leaf_slot;
    node_at[up.index] = j;
  }
};

// [listing:hploc_write_in_order]
// Place `at` of chapter 07's layout, boxes included, and the triangle numbers of its leaves in
// their slots (the triangles themselves follow in slot order, GatherTriangles: 36-byte copies
// written at scattered slots cost more than four-byte numbers). A thread per place, not per
// node: the merges numbered the nodes in the order they happened to be made, so threads in
// the nodes' order wrote 64-byte nodes all over the array; in the array's order a warp writes
// 2 KiB side by side, each node in four 16-byte stores (store_node), and its leaves' slots
// (depth first, as the places are) nearly side by side too. The walk made every box as the
// union of its children's, left one grown by the right, from the triangles' own boxes up: the
// very operations, in the very order, of the bottom-up pass that boxes the other builders'
// trees (refit.h), so its boxes are that pass's, and it need not run. A tree too deep for the
// traversal stack is not laid out: some places were never given a node.
struct WriteClusters {
  ClusterTree tree;
  const int *index, *first_slot, *node_at, *sorted_ids, *too_deep;
  BvhNode* out;
  int* triangle_ids;
  RT_HD void operator()(int at) const {
    if (*too_deep != 0) return;
    const int j = node_at[at];
    const ClusterPair pair = tree.nodes[j];
    BvhNode written;
    for (int c = 0; c < 2; ++c) {
      const int child = pair.child[c];
      const bool leaf = child < tree.n;
      // A leaf on the right comes after all the leaves of the left child.
      const int slot = first_slot[j] + (c == 1 ? tree.leaf_counts[pair.child[0]] : 0);
      written.box[c] = tree.boxes[child];
      written.first[c] = leaf ? slot : index[child - tree.n];
      written.count[c] = leaf ? 1 : 0;
      if (leaf) triangle_ids[slot] = sorted_ids[child];
    }
    store_node(&out[at], written);
  }
};
// [/listing:hploc_write_in_order]

// The arrays of one build, all made before its clock starts.
struct HplocArrays {
  BackendArray<Aabb> boxes;
  BackendArray<int> leaf_counts, parents, left_leaves;
  BackendArray<ClusterPair> nodes;
  BackendArray<unsigned long long> far_ends;
  BackendArray<int> clusters, index, first_slot, node_at, triangle_ids;
  BackendArray<unsigned> arrivals; // the treelet rounds' counters
  BackendArray<int> status; // the node counter and the too-deep flag: one read at the end
  BackendArray<BvhNode> out_nodes;
  BackendArray<TriangleF> triangles;
  HplocArrays(Backend backend, int n, int treelet_rounds)
      : boxes(backend, 2 * n - 1), leaf_counts(backend, 2 * n - 1), parents(backend, 2 * n - 1),
        left_leaves(backend, 2 * n - 1), nodes(backend, n - 1), far_ends(backend, n - 1),
        clusters(backend, n), index(backend, n - 1), first_slot(backend, n - 1),
        node_at(backend, n - 1), triangle_ids(backend, n),
        arrivals(backend, treelet_rounds > 0 ? n - 1 : 0), status(backend, 2),
        out_nodes(backend, n - 1), triangles(backend, n) {}
  ClusterTree tree(int n) {
    return {
        n, boxes.data(), leaf_counts.data(), nodes.data(), parents.data(), left_leaves.data()};
  }
};

std::optional<GpuBuild> hploc_tree(Backend backend, const ch04::Mesh& mesh, int radius,
                                   int threshold, int treelet_rounds) {
  const int n = static_cast<int>(mesh.triangles.size());
  MeshArrays d_mesh(backend, mesh);
  MortonOrder<std::uint32_t> order(backend, d_mesh.view());
  HplocArrays a(backend, n, treelet_rounds);
  a.status.fill_bytes(0);

  BackendStopwatch clock(backend); // build time: events around the kernels, or wall time
  order.sort();
  const ClusterTree tree = a.tree(n);
  for_each_index(backend, n,
                 StartLeaves{tree, order.boxes.data(), order.sorted_ids.data(),
                             a.clusters.data(), a.far_ends.data()});
  walk_up(backend, HplocWalk{tree, order.sorted_codes.data(), a.far_ends.data(),
                             a.clusters.data(), a.status.data(), radius, threshold});
  for (int round = 0; round < treelet_rounds; ++round) {
    a.arrivals.fill_bytes(0);
    restructure_round(backend,
                      RestructureTreelets{tree, a.arrivals.data(), treelet_min_leaves(round)});
  }
  for_each_index(backend, n - 1,
                 PlaceClusters{tree, a.index.data(), a.first_slot.data(), a.node_at.data(),
                               a.status.data() + 1});
  for_each_index(backend, n - 1,
                 WriteClusters{tree, a.index.data(), a.first_slot.data(), a.node_at.data(),
                               order.sorted_ids.data(), a.status.data() + 1, a.out_nodes.data(),
                               a.triangle_ids.data()});
  for_each_index(backend, n,
                 GatherTriangles{order.mesh, a.triangle_ids.data(), a.triangles.data()});
  const std::vector<int> status = a.status.to_host();
  if (status[0] != n - 1)
    throw Error("H-PLOC made " + std::to_string(status[0]) + " nodes for " + std::to_string(n) +
                " leaves");
  if (status[1] != 0) return std::nullopt; // too deep: the layout above is not used
  GpuBuild build;
  build.build_ms = clock.milliseconds();
  build.bvh.nodes = a.out_nodes.to_host();
  build.bvh.triangles = a.triangles.to_host();
  build.bvh.triangle_ids = a.triangle_ids.to_host();
  build.bvh.bounds = root_bounds(build.bvh);
  return build;
}

} // namespace

GpuBuild build_hploc(Backend backend, const ch04::Mesh& mesh, int radius, int threshold,
                     int treelet_rounds) {
  if (radius < 1 || radius > k_warp_lanes - 1)
    throw InputError("H-PLOC radius " + std::to_string(radius) + ": it takes 1 to " +
                     std::to_string(k_warp_lanes - 1));
  if (threshold < 1 || threshold > k_hploc_threshold)
    throw InputError("H-PLOC threshold " + std::to_string(threshold) + ": it takes 1 to " +
                     std::to_string(k_hploc_threshold));
  ch07::check_build_input(mesh);
  const int n = static_cast<int>(mesh.triangles.size());
  if (n < 2) return build_lbvh(backend, mesh, CodeWidth::bits30); // nothing to cluster
  if (backend == Backend::gpu)
    ch05::check_device_memory(static_cast<std::size_t>(n) * device_bytes_per_triangle(),
                              "the H-PLOC tree of " + std::to_string(n) + " triangles");
  if (treelet_rounds < 0 || treelet_rounds > k_max_treelet_rounds)
    throw InputError("treelet rounds " + std::to_string(treelet_rounds) + ": it takes 0 to " +
                     std::to_string(k_max_treelet_rounds));
  std::optional<GpuBuild> built = hploc_tree(backend, mesh, radius, threshold, treelet_rounds);
  if (!built) {
    GpuBuild lbvh = build_lbvh(backend, mesh, CodeWidth::bits30);
    lbvh.note = "H-PLOC's tree was deeper than the traversal stack; built as the 30-bit LBVH";
    return lbvh;
  }
  built->bvh.options.method = ch07::SplitMethod::sah; // merged by surface area
  built->bvh.options.max_leaf_size = 1;
  built->bvh.stats.build_ms = built->build_ms;
  fill_stats(built->bvh);
  return std::move(*built);
}

} // namespace rt::ch10
