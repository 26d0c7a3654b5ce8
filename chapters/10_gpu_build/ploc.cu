// Chapter 10: PLOC, parallel locally-ordered clustering (Meister & Bittner 2018), pass by
// pass. See gpu_build.h. The LBVH splits where the Morton code's bits say; PLOC merges what is
// near in space, bottom up, and looks at the boxes to do it, so its trees cost fewer ray
// steps. Every round is a few passes of for_each_index and two prefix sums; nothing in a
// round depends on the order threads run in, so both backends make the same tree.
#include "gpu_build.h"

#include <algorithm>
#include <numeric>
#include <string>

#include "build_passes.cuh"
#include "bvh_build.h"
#include "cluster_tree.h"
#include "model_render.h"
#include "rt/error.h"

namespace rt::ch10 {
namespace {

using namespace passes;

// The start: one cluster per leaf, boxed.
struct StartClusters {
  ClusterTree tree;
  const Aabb* triangle_boxes;
  const int* sorted_ids;
  int* clusters;
  RT_HD void operator()(int k) const {
    tree.boxes[k] = triangle_boxes[sorted_ids[k]];
    tree.leaf_counts[k] = 1;
    clusters[k] = k;
  }
};

// [listing:ploc_neighbour]
// Each cluster's nearest neighbour within `radius` places on either side: the one whose box
// merged with its own has the smallest surface area, the leftmost of equal ones (the first
// the loop meets), so the choice depends on nothing but the boxes and their places.
struct FindNeighbours {
  ClusterTree tree;
  const int* clusters;
  int count, radius;
  int* neighbour;
  RT_HD void operator()(int i) const {
    const Aabb own = tree.boxes[clusters[i]];
    float best_area = 0.0f;
    int best = -1;
    const int lo = i - radius < 0 ? 0 : i - radius;
    const int hi = i + radius >= count ? count - 1 : i + radius;
    for (int j = lo; j <= hi; ++j) {
      if (j == i) continue;
      Aabb merged = own;
      merged.grow(tree.boxes[clusters[j]]);
      const float area = merged.half_area();
      if (best < 0 || area < best_area) {
        best_area = area;
        best = j;
      }
    }
    neighbour[i] = best;
  }
};
// [/listing:ploc_neighbour]

// [listing:ploc_merge]
// Two clusters that chose each other merge: the left one makes the new node, in its own place,
// and the right one leaves. Some pair always chooses each other: the leftmost cluster in a
// pair of the smallest merged area of all chooses the leftmost of its partners of that area,
// and that one chooses it back, since no cluster further left is in such a pair. So every
// round merges at least once; and that may be all it does (ploc_round_bound).
struct MarkMerges {
  const int* neighbour;
  int* makes_node; // 1 where a cluster makes a node
  int* stays;      // 1 where a cluster is still one after the round
  RT_HD void operator()(int i) const {
    const int j = neighbour[i];
    const bool mutual = j >= 0 && neighbour[j] == i;
    makes_node[i] = mutual && i < j;
    stays[i] = !(mutual && i > j);
  }
};

// Whether a round pairs its clusters in place order instead: when its mutual pairs (the last
// prefix of makes_node plus the last flag) are fewer than one in k_ploc_ordered_share.
RT_HD inline bool pairs_in_order(const int* makes_node, const int* node_offset, int count) {
  const long long mutual_pairs = node_offset[count - 1] + makes_node[count - 1];
  return mutual_pairs * k_ploc_ordered_share < count;
}

// The round's new nodes and the clusters that go on: at places the prefix sums gave them, or
// in a round that pairs in place order, cluster 2k with 2k + 1 into node k, at place k.
struct MergeClusters {
  ClusterTree tree;
  const int *clusters, *neighbour, *makes_node, *stays, *node_offset, *place;
  int count;
  int first_new; // the node number of this round's first new node
  int* next_clusters;
  RT_HD void operator()(int i) const {
    int partner = -1, offset = 0, at = 0;
    if (pairs_in_order(makes_node, node_offset, count)) {
      if (i % 2 == 1) return;
      partner = i + 1 < count ? i + 1 : -1;
      offset = at = i / 2;
    } else {
      if (!stays[i]) return;
      partner = makes_node[i] ? neighbour[i] : -1;
      offset = node_offset[i];
      at = place[i];
    }
    if (partner < 0) {
      next_clusters[at] = clusters[i];
      return;
    }
    const int a = clusters[i], b = clusters[partner];
    const int id = first_new + offset, interior = id - tree.n;
    Aabb box = tree.boxes[a];
    box.grow(tree.boxes[b]);
    tree.boxes[id] = box;
    const int leaves_a = tree.leaf_counts[a];
    tree.leaf_counts[id] = leaves_a + tree.leaf_counts[b];
    link_children(tree, interior, a, b, leaves_a);
    next_clusters[at] = id;
  }
};
// [/listing:ploc_merge]

// How many nodes the round made and clusters it kept (the last prefix plus the last flag, or
// half of them when it paired in order), and whether it paired in order.
struct RoundTotals {
  const int *makes_node, *stays, *node_offset, *place;
  int count;
  int* totals;
  RT_HD void operator()(int) const {
    const int last = count - 1;
    const bool in_order = pairs_in_order(makes_node, node_offset, count);
    totals[0] = in_order ? count / 2 : node_offset[last] + makes_node[last];
    totals[1] = in_order ? (count + 1) / 2 : place[last] + stays[last];
    totals[2] = in_order;
  }
};

// [listing:ploc_place]
// Every node's place in chapter 07's arrays (cluster_tree.h); the walk stops at chapter 07's
// depth bound, and a leaf may sit one level below the deepest interior node allowed.
struct PlacePloc {
  ClusterTree tree;
  int* index; // of each interior node
  int* slot;  // of each leaf
  int* too_deep;
  RT_HD void operator()(int id) const {
    const bool leaf = id < tree.n;
    const WayUp up =
        place_on_way_up(tree, id, leaf ? ch07::k_max_bvh_depth : ch07::k_max_bvh_depth - 1);
    if (up.too_deep) {
      mark(too_deep);
    } else if (leaf) {
      slot[id] = up.leaf_slot;
    } else {
      index[id - tree.n] = up.index;
    }
  }
};
// [/listing:ploc_place]

// Interior node j in chapter 07's layout, and its leaves' triangles in their slots.
struct WritePloc {
  ClusterTree tree;
  const int *index, *slot, *sorted_ids;
  MeshView mesh;
  BvhNode* out;
  int* out_parents;
  TriangleF* triangles;
  int* triangle_ids;
  RT_HD void operator()(int j) const {
    const int at = index[j];
    BvhNode written;
    for (int c = 0; c < 2; ++c) {
      const int child = tree.nodes[j].child[c];
      const bool leaf = child < tree.n;
      written.first[c] = leaf ? slot[child] : index[child - tree.n];
      written.count[c] = leaf ? 1 : 0;
      if (leaf) {
        triangles[slot[child]] = mesh.triangle(sorted_ids[child]);
        triangle_ids[slot[child]] = sorted_ids[child];
      } else {
        out_parents[written.first[c]] = 2 * at + c;
      }
    }
    out[at] = written;
    if (at == 0) out_parents[0] = -1;
  }
};

// Prefix sums of the round's flags (exclusive), CUB's on the GPU.
void exclusive_sum(Backend backend, BackendArray<int>& in, BackendArray<int>& out, int count,
                   BackendArray<unsigned char>& scratch) {
  if (backend == Backend::cpu) {
    std::exclusive_scan(in.data(), in.data() + count, out.data(), 0);
    return;
  }
  std::size_t bytes = scratch.size();
  RT_CUDA_CHECK(
      cub::DeviceScan::ExclusiveSum(scratch.data(), bytes, in.data(), out.data(), count));
}

std::size_t scan_scratch_bytes(int n) {
  std::size_t bytes = 0;
  RT_CUDA_CHECK(cub::DeviceScan::ExclusiveSum(nullptr, bytes, static_cast<int*>(nullptr),
                                              static_cast<int*>(nullptr), n));
  return std::max<std::size_t>(bytes, 1);
}

// The arrays of one build.
struct PlocArrays {
  BackendArray<Aabb> boxes;
  BackendArray<int> leaf_counts, parents, left_leaves;
  BackendArray<ClusterPair> nodes;
  BackendArray<int> clusters, next_clusters, neighbour, makes_node, stays, node_offset, place,
      totals;
  BackendArray<unsigned char> scan_scratch;
  PlocArrays(Backend backend, int n)
      : boxes(backend, 2 * n - 1), leaf_counts(backend, 2 * n - 1), parents(backend, 2 * n - 1),
        left_leaves(backend, 2 * n - 1), nodes(backend, n - 1), clusters(backend, n),
        next_clusters(backend, n), neighbour(backend, n), makes_node(backend, n),
        stays(backend, n), node_offset(backend, n), place(backend, n), totals(backend, 3),
        scan_scratch(backend, backend == Backend::gpu ? scan_scratch_bytes(n) : 0) {}
  ClusterTree tree(int n) {
    return {
        n, boxes.data(), leaf_counts.data(), nodes.data(), parents.data(), left_leaves.data()};
  }
};

// How many rounds the clustering ran, and how many of them paired in order.
struct RoundCounts {
  int rounds = 0, in_order = 0;
};

// The clustering rounds, until one cluster is left.
RoundCounts cluster(Backend backend, PlocArrays& a, int n, int radius) {
  const ClusterTree tree = a.tree(n);
  const int bound = ploc_round_bound(n);
  int count = n, made = 0;
  RoundCounts counts;
  while (count > 1) {
    if (++counts.rounds > bound) throw Error("PLOC ran past its round bound: see the proof");
    for_each_index(backend, count,
                   FindNeighbours{tree, a.clusters.data(), count, radius, a.neighbour.data()});
    for_each_index(backend, count,
                   MarkMerges{a.neighbour.data(), a.makes_node.data(), a.stays.data()});
    exclusive_sum(backend, a.makes_node, a.node_offset, count, a.scan_scratch);
    exclusive_sum(backend, a.stays, a.place, count, a.scan_scratch);
    for_each_index(backend, count,
                   MergeClusters{tree, a.clusters.data(), a.neighbour.data(),
                                 a.makes_node.data(), a.stays.data(), a.node_offset.data(),
                                 a.place.data(), count, n + made, a.next_clusters.data()});
    for_each_index(backend, 1,
                   RoundTotals{a.makes_node.data(), a.stays.data(), a.node_offset.data(),
                               a.place.data(), count, a.totals.data()});
    const std::vector<int> totals = a.totals.to_host();
    made += totals[0];
    count = totals[1];
    counts.in_order += totals[2];
    std::swap(a.clusters, a.next_clusters);
  }
  return counts;
}

std::optional<GpuBuild> ploc_tree(Backend backend, const ch04::Mesh& mesh, int radius,
                                  RoundCounts& counts) {
  const int n = static_cast<int>(mesh.triangles.size());
  MeshArrays d_mesh(backend, mesh);
  MortonOrder<std::uint32_t> order(backend, d_mesh.view());
  PlocArrays a(backend, n);
  BackendArray<int> index(backend, n - 1), slot(backend, n), out_parents(backend, n - 1),
      triangle_ids(backend, n), too_deep(backend, 1);
  BackendArray<BvhNode> nodes(backend, n - 1);
  BackendArray<TriangleF> triangles(backend, n);
  BackendArray<unsigned> arrivals(backend, n - 1);
  a.parents.fill_bytes(0xff); // -1: no parent yet
  too_deep.fill_bytes(0);

  BackendStopwatch clock(backend); // build time: events around the kernels, or wall time
  order.sort();
  const ClusterTree tree = a.tree(n);
  for_each_index(
      backend, n,
      StartClusters{tree, order.boxes.data(), order.sorted_ids.data(), a.clusters.data()});
  counts = cluster(backend, a, n, radius);
  for_each_index(backend, 2 * n - 1,
                 PlacePloc{tree, index.data(), slot.data(), too_deep.data()});
  if (too_deep.to_host()[0] != 0) return std::nullopt;
  for_each_index(backend, n - 1,
                 WritePloc{tree, index.data(), slot.data(), order.sorted_ids.data(), order.mesh,
                           nodes.data(), out_parents.data(), triangles.data(),
                           triangle_ids.data()});
  box_bottom_up(backend, nodes, out_parents, triangles, arrivals);
  GpuBuild build;
  build.build_ms = clock.milliseconds();
  build.bvh.nodes = nodes.to_host();
  build.bvh.triangles = triangles.to_host();
  build.bvh.triangle_ids = triangle_ids.to_host();
  build.bvh.bounds = root_bounds(build.bvh);
  return build;
}

} // namespace

// [listing:ploc_round_bound]
// Why PLOC's rounds are few whatever the input. A round that starts with c clusters and
// merges m mutual pairs leaves c - m, and nothing bounds m from below but 1 (MarkMerges):
// where every cluster's nearest neighbour is its left one (centroids spaced ever wider), or
// where all are equally near (identical boxes, or boxes on a line, all merged areas equal, the
// leftmost chosen), one pair is all a round merges, and n - 1 rounds do n^2 work. So a round
// whose mutual pairs are fewer than c / F (F = k_ploc_ordered_share) pairs all of its clusters
// in place order instead, and leaves ceil(c / 2) <= c - ceil(c / F) of them; any other round
// leaves c - m <= c - ceil(c / F). With m >= 1 too, every round removes at least
// max(1, ceil(c / F)) clusters, a fixed share: O(F log n) rounds, counted here exactly. A pair
// in place order need not be near, so F is set where no model of the benchmark set goes (its
// fewest mutual pairs in a round of more than F clusters are about one in twelve), and such
// rounds are left to input that has no nearest neighbours to speak of.
int ploc_round_bound(long long n) {
  int rounds = 0;
  for (long long c = n; c > 1; ++rounds)
    c -= std::max(1LL, (c + k_ploc_ordered_share - 1) / k_ploc_ordered_share);
  return rounds;
}
// [/listing:ploc_round_bound]

GpuBuild build_ploc(Backend backend, const ch04::Mesh& mesh, int radius) {
  if (radius < 1 || radius > 64)
    throw InputError("PLOC radius " + std::to_string(radius) + ": it takes 1 to 64");
  ch07::check_build_input(mesh);
  const int n = static_cast<int>(mesh.triangles.size());
  if (n < 2) return build_lbvh(backend, mesh, CodeWidth::bits30); // nothing to cluster
  if (backend == Backend::gpu)
    ch05::check_device_memory(static_cast<std::size_t>(n) * device_bytes_per_triangle(),
                              "the PLOC tree of " + std::to_string(n) + " triangles");
  RoundCounts counts;
  std::optional<GpuBuild> built = ploc_tree(backend, mesh, radius, counts);
  if (!built) {
    built = build_lbvh(backend, mesh, CodeWidth::bits30);
    built->note = "PLOC's tree was deeper than the traversal stack; built as the 30-bit LBVH";
  }
  built->rounds = counts.rounds;
  built->rounds_in_order = counts.in_order;
  if (!built->note.empty()) return std::move(*built);
  built->bvh.options.method = ch07::SplitMethod::sah; // merged by surface area
  built->bvh.options.max_leaf_size = 1;
  built->bvh.stats.build_ms = built->build_ms;
  fill_stats(built->bvh);
  return std::move(*built);
}

} // namespace rt::ch10
