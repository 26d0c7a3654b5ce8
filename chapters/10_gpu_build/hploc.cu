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
#include "hploc.h"
#include "model_render.h"
#include "rt/error.h"

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
  int* far_ends;
  RT_HD void operator()(int k) const {
    tree.boxes[k] = triangle_boxes[sorted_ids[k]];
    tree.leaf_counts[k] = 1;
    tree.parents[k] = -1;
    clusters[k] = k;
    if (k < tree.n - 1) {
      far_ends[k] = -1;
      tree.parents[tree.n + k] = -1;
    }
  }
};

// What the walk reads and writes.
struct HplocWalk {
  ClusterTree tree;
  const std::uint32_t* codes; // sorted
  int* far_ends;              // n - 1: the first arrival's far end at each node, or -1
  int* clusters;              // n: each subtree's list, from the start of its range
  int* node_counter;          // interior nodes made so far
  int radius, threshold;
  // The most clusters a completed subtree's list keeps: the threshold, one at the root.
  RT_HD int target(int first, int last) const {
    return first == 0 && last == tree.n - 1 ? 1 : threshold;
  }
};

// ---- The CPU backend: a thread per leaf, the warp's lanes in a loop -------------------------

// New nodes from the shared counter, written into the tree.
struct CpuNodes {
  const HplocWalk& walk;
  int reserve(int count) { return walk.tree.n + reserve_nodes(walk.node_counter, count); }
  void write(int node, int left, int right, const Aabb& box, int leaves) {
    write_cluster_node(walk.tree, node, left, right, box, leaves);
  }
};

// The two children's lists side by side: the left child's from `first`, the right child's
// from `split`, each up to its first -1 or its slots_to_read.
ClusterList gather_lists(const HplocWalk& walk, int first, int split, int last) {
  ClusterList list;
  for (int side = 0; side < 2; ++side) {
    const int start = side == 0 ? first : split;
    const int slots =
        slots_to_read(side == 0 ? split - first : last - split + 1, walk.threshold);
    for (int k = 0; k < slots; ++k) {
      const int id = walk.clusters[start + k];
      if (id < 0) break;
      list.id[list.count] = id;
      list.box[list.count] = walk.tree.boxes[id];
      list.leaves[list.count] = walk.tree.leaf_counts[id];
      ++list.count;
    }
  }
  return list;
}

void climb_on_cpu(const HplocWalk& walk, int leaf) {
  const int n = walk.tree.n;
  int first = leaf, last = leaf, split = 0;
  CpuNodes nodes{walk};
  while (climb(walk.codes, n, walk.far_ends, first, last, split)) {
    if (!gathers(first, last, n, walk.threshold)) continue;
    ClusterList list = gather_lists(walk, first, split, last);
    merge_cluster_list(list, walk.target(first, last), walk.radius, nodes);
    for (int k = 0; k < list.count; ++k) walk.clusters[first + k] = list.id[k];
    if (list.count < slots_to_read(last - first + 1, walk.threshold))
      walk.clusters[first + list.count] = -1;
    if (first == 0 && last == n - 1) return;
  }
}

// ---- The GPU backend: a thread per leaf, a warp per list ------------------------------------

#if RT_DEVICE_CODE_POSSIBLE
constexpr unsigned k_all_lanes = 0xffffffffu;
constexpr int k_hploc_block = 128; // threads per block of the walk: four warps

// A box from another lane, six shuffles.
__device__ Aabb shuffle_box(const Aabb& box, int from) {
  Aabb out;
  out.lo = {__shfl_sync(k_all_lanes, box.lo.x, from), __shfl_sync(k_all_lanes, box.lo.y, from),
            __shfl_sync(k_all_lanes, box.lo.z, from)};
  out.hi = {__shfl_sync(k_all_lanes, box.hi.x, from), __shfl_sync(k_all_lanes, box.hi.y, from),
            __shfl_sync(k_all_lanes, box.hi.z, from)};
  return out;
}

// Boxes another thread wrote during the walk, read past the L1 cache (refit.h's reason).
__device__ Aabb load_box(const Aabb& box) {
  const volatile float* f = &box.lo.x;
  Aabb out;
  out.lo = {f[0], f[1], f[2]};
  out.hi = {f[3], f[4], f[5]};
  return out;
}
__device__ int load_int(const int* p) { return *static_cast<const volatile int*>(p); }

// [listing:hploc_nearest_warp]
// nearest_cluster on the warp: the lane computes the cost of its merge with the lane d places
// to its right, whose box comes down by a shuffle, and hands the cost up to that lane by
// another, so each of the 2 * radius candidates costs one box shuffle per pair, not one per
// lane. The costs are merge_cost's, left box first, as on the CPU; better_candidate makes the
// order they come in irrelevant.
__device__ int nearest_on_warp(int lane, int count, int radius, const Aabb& own) {
  int best = -1;
  float best_cost = 0.0f;
  for (int d = 1; d <= radius; ++d) {
    Aabb right;
    right.lo = {__shfl_down_sync(k_all_lanes, own.lo.x, d),
                __shfl_down_sync(k_all_lanes, own.lo.y, d),
                __shfl_down_sync(k_all_lanes, own.lo.z, d)};
    right.hi = {__shfl_down_sync(k_all_lanes, own.hi.x, d),
                __shfl_down_sync(k_all_lanes, own.hi.y, d),
                __shfl_down_sync(k_all_lanes, own.hi.z, d)};
    const float cost = merge_cost(own, right); // with lane + d, if it is in the list
    const float from_left = __shfl_up_sync(k_all_lanes, cost, d); // lane - d's, with this lane
    if (lane + d < count && better_candidate(cost, lane + d, best_cost, best)) {
      best = lane + d;
      best_cost = cost;
    }
    if (lane < count && lane - d >= 0 &&
        better_candidate(from_left, lane - d, best_cost, best)) {
      best = lane - d;
      best_cost = from_left;
    }
  }
  return best;
}
// [/listing:hploc_nearest_warp]

// [listing:hploc_merge_warp]
// The list of the subtree first..last, merged by the whole warp, one cluster per lane: lanes
// 0-15 read the left child's list, lanes 16-31 the right child's, a vote counts each, and
// shuffles close the gap. Then merge_cluster_list's steps, a lane each: the nearest
// neighbour through shuffles, the mutual pairs by a vote, one atomic for the warp's new
// nodes, and the list closed up by shuffles from the lanes that stay.
__device__ void merge_on_warp(const HplocWalk& walk, int lane, int first, int split, int last) {
  const int half = lane / k_hploc_threshold, slot = lane % k_hploc_threshold;
  const int start = half == 0 ? first : split;
  const int size = half == 0 ? split - first : last - split + 1;
  int id =
      slot < slots_to_read(size, walk.threshold) ? load_int(&walk.clusters[start + slot]) : -1;
  const unsigned missing = __ballot_sync(k_all_lanes, id < 0);
  const int left_count = __ffs((missing & 0xffffu) | 0x10000u) - 1;
  const int right_count = __ffs((missing >> 16) | 0x10000u) - 1;
  int count = left_count + right_count;
  id = __shfl_sync(k_all_lanes, id,
                   lane < left_count ? lane : k_hploc_threshold + lane - left_count);
  Aabb box;
  int leaves = 0;
  if (lane < count) {
    box = load_box(walk.tree.boxes[id]);
    leaves = load_int(&walk.tree.leaf_counts[id]);
  }
  const int target = walk.target(first, last);
  while (count > target) {
    const int j = nearest_on_warp(lane, count, walk.radius, box);
    const int back = __shfl_sync(k_all_lanes, j, j < 0 ? lane : j);
    const bool mutual = lane < count && j >= 0 && back == lane;
    const unsigned makes = __ballot_sync(k_all_lanes, mutual && lane < j);
    const unsigned stays = __ballot_sync(k_all_lanes, lane < count && !(mutual && lane > j));
    int first_node = 0;
    if (lane == 0)
      first_node = walk.tree.n + reserve_nodes(walk.node_counter, count_bits(makes));
    first_node = __shfl_sync(k_all_lanes, first_node, 0);
    const bool make = (makes >> lane & 1u) != 0;
    const int partner = make ? j : lane;
    const Aabb partner_box = shuffle_box(box, partner);
    const int partner_id = __shfl_sync(k_all_lanes, id, partner);
    const int partner_leaves = __shfl_sync(k_all_lanes, leaves, partner);
    if (make) {
      box.grow(partner_box);
      leaves += partner_leaves;
      const int node = first_node + count_bits(makes & lanes_below(lane));
      write_cluster_node(walk.tree, node, id, partner_id, box, leaves);
      id = node;
    }
    count = count_bits(stays);
    const int from = lane < count ? nth_set_bit(stays, lane) : lane;
    id = __shfl_sync(k_all_lanes, id, from);
    box = shuffle_box(box, from);
    leaves = __shfl_sync(k_all_lanes, leaves, from);
  }
  if (lane < count) walk.clusters[first + lane] = id;
  if (lane == count && count < slots_to_read(last - first + 1, walk.threshold))
    walk.clusters[first + lane] = -1;
  __threadfence(); // this lane's nodes and list, seen before the owner's exchange
  __syncwarp();
}
// [/listing:hploc_merge_warp]

// [listing:hploc_kernel]
// The whole walk in one kernel. Every lane stays in the loop until no lane of its warp
// climbs, because the merges need all 32; after each step up, the lanes whose subtree needs
// its list looked at are taken one at a time (a vote lists them), the warp merging each.
__global__ void hploc_kernel(HplocWalk walk) {
  const int n = walk.tree.n;
  const int leaf = blockIdx.x * blockDim.x + threadIdx.x;
  const int lane = threadIdx.x % k_warp_lanes;
  int first = leaf, last = leaf, split = 0;
  bool climbing = leaf < n;
  while (__any_sync(k_all_lanes, climbing)) {
    if (climbing) climbing = climb(walk.codes, n, walk.far_ends, first, last, split);
    unsigned waiting =
        __ballot_sync(k_all_lanes, climbing && gathers(first, last, n, walk.threshold));
    while (waiting != 0) {
      const int owner = __ffs(waiting) - 1;
      waiting &= waiting - 1;
      merge_on_warp(walk, lane, __shfl_sync(k_all_lanes, first, owner),
                    __shfl_sync(k_all_lanes, split, owner),
                    __shfl_sync(k_all_lanes, last, owner));
    }
    if (first == 0 && last == n - 1) climbing = false; // the root: done
  }
}
// [/listing:hploc_kernel]
#endif

void walk_up(Backend backend, const HplocWalk& walk) {
  const int n = walk.tree.n;
  if (backend == Backend::cpu) {
    for_each_index_cpu(
        static_cast<std::size_t>(n), [&](std::size_t leaf) { climb_on_cpu(walk, int(leaf)); },
        cpu_thread_count(), "leaves");
    return;
  }
#if RT_DEVICE_CODE_POSSIBLE
  hploc_kernel<<<blocks_to_cover(n, k_hploc_block), k_hploc_block>>>(walk);
  RT_CUDA_CHECK_LAUNCH("hploc_kernel");
#endif
}

// Interior node j's place in chapter 07's arrays and the slot of its first leaf, counted on
// the way up as PLOC's are (ploc.cu). Only interior nodes walk: a leaf's slot follows from its
// parent's first slot (WriteClusters), and a leaf may sit one level below the deepest
// interior node allowed, so the interior nodes' depth check is the whole tree's.
struct PlaceClusters {
  ClusterTree tree;
  int* index;      // of each interior node
  int* first_slot; // of each interior node's first leaf
  int* too_deep;
  RT_HD void operator()(int j) const {
    int place = 0, leaf_slot = 0, depth = 0;
    for (int x = tree.n + j; tree.parents[x] >= 0;) {
      if (++depth > ch07::k_max_bvh_depth - 1) {
        mark(too_deep);
        return;
      }
      const int parent = tree.parents[x] >> 1;
      const int left = tree.nodes[parent].child[0];
      const bool right = (tree.parents[x] & 1) != 0;
      place += right ? tree.leaf_counts[left] : 1;
      leaf_slot += right ? tree.leaf_counts[left] : 0;
      x = tree.n + parent;
    }
    index[j] = place;
    first_slot[j] = leaf_slot;
  }
};

// Interior node j in chapter 07's layout, boxes included, and its leaves' triangles in their
// slots. The walk made every box as the union of its children's, left one grown by the right,
// from the triangles' own boxes up: the very operations, in the very order, of the bottom-up
// pass that boxes the other builders' trees (refit.h), so its boxes are that pass's, and it
// need not run.
struct WriteClusters {
  ClusterTree tree;
  const int *index, *first_slot, *sorted_ids;
  MeshView mesh;
  BvhNode* out;
  TriangleF* triangles;
  int* triangle_ids;
  RT_HD void operator()(int j) const {
    const int at = index[j];
    BvhNode written;
    for (int c = 0; c < 2; ++c) {
      const int child = tree.nodes[j].child[c];
      const bool leaf = child < tree.n;
      // A leaf on the right comes after all the leaves of the left child.
      const int slot = first_slot[j] + (c == 1 ? tree.leaf_counts[tree.nodes[j].child[0]] : 0);
      written.box[c] = tree.boxes[child];
      written.first[c] = leaf ? slot : index[child - tree.n];
      written.count[c] = leaf ? 1 : 0;
      if (leaf) {
        triangles[slot] = mesh.triangle(sorted_ids[child]);
        triangle_ids[slot] = sorted_ids[child];
      }
    }
    out[at] = written;
  }
};

// The arrays of one build, all made before its clock starts.
struct HplocArrays {
  BackendArray<Aabb> boxes;
  BackendArray<int> leaf_counts, parents;
  BackendArray<ClusterPair> nodes;
  BackendArray<int> clusters, far_ends, index, first_slot, triangle_ids;
  BackendArray<int> status; // the node counter and the too-deep flag: one read at the end
  BackendArray<BvhNode> out_nodes;
  BackendArray<TriangleF> triangles;
  HplocArrays(Backend backend, int n)
      : boxes(backend, 2 * n - 1), leaf_counts(backend, 2 * n - 1), parents(backend, 2 * n - 1),
        nodes(backend, n - 1), clusters(backend, n), far_ends(backend, n - 1),
        index(backend, n - 1), first_slot(backend, n - 1), triangle_ids(backend, n),
        status(backend, 2), out_nodes(backend, n - 1), triangles(backend, n) {}
  ClusterTree tree(int n) {
    return {n, boxes.data(), leaf_counts.data(), nodes.data(), parents.data()};
  }
};

std::optional<GpuBuild> hploc_tree(Backend backend, const ch04::Mesh& mesh, int radius,
                                   int threshold) {
  const int n = static_cast<int>(mesh.triangles.size());
  MeshArrays d_mesh(backend, mesh);
  MortonOrder<std::uint32_t> order(backend, d_mesh.view());
  HplocArrays a(backend, n);
  a.status.fill_bytes(0);

  BackendStopwatch clock(backend); // build time: events around the kernels, or wall time
  order.sort();
  const ClusterTree tree = a.tree(n);
  for_each_index(backend, n,
                 StartLeaves{tree, order.boxes.data(), order.sorted_ids.data(),
                             a.clusters.data(), a.far_ends.data()});
  walk_up(backend, HplocWalk{tree, order.sorted_codes.data(), a.far_ends.data(),
                             a.clusters.data(), a.status.data(), radius, threshold});
  for_each_index(backend, n - 1,
                 PlaceClusters{tree, a.index.data(), a.first_slot.data(), a.status.data() + 1});
  for_each_index(backend, n - 1,
                 WriteClusters{tree, a.index.data(), a.first_slot.data(),
                               order.sorted_ids.data(), order.mesh, a.out_nodes.data(),
                               a.triangles.data(), a.triangle_ids.data()});
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

GpuBuild build_hploc(Backend backend, const ch04::Mesh& mesh, int radius, int threshold) {
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
  std::optional<GpuBuild> built = hploc_tree(backend, mesh, radius, threshold);
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
