// Chapter 10 tests of H-PLOC: one list's merge against a plain PLOC written out here, on the
// same clusters; trees that pass chapter 07's checker and give brute force's hits; a cost near
// PLOC's and below the LBVH's; the threshold that makes it the LBVH, and thresholds and radii
// that change the tree; degenerate input within the depth bound or handed to the LBVH; no ray
// leaking out of closed meshes; bad input refused. The treelet search against making every
// tree, a worst-shaped treelet rewired, rounds that lower the cost and keep the tree exact.
// The [gpu] cases: the GPU's tree is the CPU threads', bit for bit.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "07_bvh/bvh_cases.h"
#include "adversarial_rays.h"
#include "build_cases.h"
#include "bvh_build.h"
#include "check_bvh.h"
#include "collapse.h"
#include "gpu_build.h"
#include "gpu_guard.h"
#include "hploc.h"
#include "hploc_walk.h"
#include "leak_configurations.h"
#include "rt/error.h"
#include "treelets.h"
#include "wide_collapse.h"

#include <ucontext.h>

using namespace rt;
using namespace rt::ch10;
using namespace rt::ch10::testing;

namespace {

// A node a merge made: its number, its two clusters, its box and its leaves.
struct MadeNode {
  int node, left, right;
  Aabb box;
  int leaves;
  bool operator==(const MadeNode& o) const {
    return node == o.node && left == o.left && right == o.right &&
           rt::testing::same_bits(box, o.box) && leaves == o.leaves;
  }
};

// merge_cluster_list's nodes, numbered from `next` on, kept in the order they are written.
struct RecordedNodes {
  int next = 1000;
  std::vector<MadeNode> made;
  int reserve(int count) {
    const int first = next;
    next += count;
    return first;
  }
  void write(int node, int left, int right, const Aabb& box, int leaves, int leaves_left) {
    CHECK(leaves_left >= 1);
    CHECK(leaves_left < leaves);
    made.push_back({node, left, right, box, leaves});
  }
};

struct Cluster {
  int id;
  Aabb box;
  int leaves;
};

// PLOC on one list, written as plainly as it is described: every cluster scans its neighbours
// within the radius from the left and keeps the first of the cheapest (the leftmost, unless
// `rightmost` asks for the wrong tie-break); mutual pairs merge into the left one's place, in
// list order; repeat until `target` are left.
std::vector<MadeNode> plain_ploc(std::vector<Cluster>& list, int target, int radius,
                                 bool rightmost = false) {
  std::vector<MadeNode> made;
  int next = 1000;
  while (static_cast<int>(list.size()) > target) {
    const int count = static_cast<int>(list.size());
    std::vector<int> nearest(count, -1);
    for (int i = 0; i < count; ++i) {
      float best = 0.0f;
      for (int j = std::max(0, i - radius); j <= std::min(count - 1, i + radius); ++j) {
        if (j == i) continue;
        Aabb merged = list[std::min(i, j)].box;
        merged.grow(list[std::max(i, j)].box);
        float cost = merged.half_area();
        if (std::isnan(cost)) cost = std::numeric_limits<float>::infinity();
        if (nearest[i] < 0 || cost < best || (rightmost && cost == best)) {
          best = cost;
          nearest[i] = j;
        }
      }
    }
    std::vector<Cluster> next_list;
    for (int i = 0; i < count; ++i) {
      const int j = nearest[i];
      const bool mutual = j >= 0 && nearest[j] == i;
      if (mutual && i > j) continue;
      if (!mutual) {
        next_list.push_back(list[i]);
        continue;
      }
      Aabb box = list[i].box;
      box.grow(list[j].box);
      const MadeNode node{next++, list[i].id, list[j].id, box, list[i].leaves + list[j].leaves};
      made.push_back(node);
      next_list.push_back({node.node, box, node.leaves});
    }
    list = next_list;
  }
  return made;
}

// A list of `count` random boxes; with `ties`, a few shapes repeated, so that costs tie.
// The warps that cover `threads` threads, in an order shuffled by `seed`: the order in which a
// GPU might run them is not the order of their numbers.
std::vector<int> scrambled_warps(int threads, unsigned seed) {
  std::vector<int> order((threads + k_warp_lanes - 1) / k_warp_lanes);
  for (std::size_t w = 0; w < order.size(); ++w) order[w] = static_cast<int>(w);
  std::shuffle(order.begin(), order.end(), std::mt19937(seed));
  return order;
}

std::vector<Cluster> random_clusters(std::mt19937& rng, int count, bool ties) {
  std::uniform_real_distribution<float> where(-10.0f, 10.0f), size(0.01f, 2.0f);
  std::vector<Cluster> list;
  for (int k = 0; k < count; ++k) {
    Vec3f lo{where(rng), where(rng), where(rng)};
    if (ties) lo = {float(k % 3), 0.0f, 0.0f};
    const Vec3f hi =
        lo + (ties ? Vec3f{1.0f, 1.0f, 1.0f} : Vec3f{size(rng), size(rng), size(rng)});
    Aabb box;
    box.grow(lo);
    box.grow(hi);
    list.push_back({k, box, 1 + k % 5});
  }
  return list;
}

ClusterList to_lanes(const std::vector<Cluster>& list) {
  ClusterList lanes;
  for (const Cluster& c : list) {
    lanes.id[lanes.count] = c.id;
    lanes.box[lanes.count] = c.box;
    lanes.leaves[lanes.count] = c.leaves;
    ++lanes.count;
  }
  return lanes;
}

std::vector<int> ids_of(const ClusterList& lanes) { return {lanes.id, lanes.id + lanes.count}; }
std::vector<int> ids_of(const std::vector<Cluster>& list) {
  std::vector<int> ids;
  for (const Cluster& c : list) ids.push_back(c.id);
  return ids;
}

bool same_tree(const ch07::Bvh& a, const ch07::Bvh& b) {
  return rt::testing::same_bits(a.nodes, b.nodes) && a.triangle_ids == b.triangle_ids &&
         rt::testing::same_bits(a.triangles, b.triangles);
}

// The 32 lanes of a warp as fibers on the calling thread: each runs until it calls one of
// the warp's collective operations, and when every lane has, the operation's results are
// handed out and the lanes go on. So walk_on_warp, the GPU's code, runs here as on a warp, in
// lockstep; and a collective that not every lane calls, or not the same one, is caught.
class FiberWarp {
public:
  enum class Op { none, ballot, any, shfl, shfl_down, shfl_up, sync, publish };

  // What walk_on_warp calls: lane `lane` of this warp.
  struct Lane {
    FiberWarp* warp;
    int lane;
    unsigned ballot(bool p) { return warp->collective(lane, Op::ballot, p, 0); }
    bool any(bool p) { return warp->collective(lane, Op::any, p, 0) != 0; }
    int shfl(int v, int from) {
      return static_cast<int>(
          warp->collective(lane, Op::shfl, std::bit_cast<unsigned>(v), from));
    }
    float shfl(float v, int from) {
      return std::bit_cast<float>(
          warp->collective(lane, Op::shfl, std::bit_cast<unsigned>(v), from));
    }
    float shfl_down(float v, int d) {
      return std::bit_cast<float>(
          warp->collective(lane, Op::shfl_down, std::bit_cast<unsigned>(v), d));
    }
    float shfl_up(float v, int d) {
      return std::bit_cast<float>(
          warp->collective(lane, Op::shfl_up, std::bit_cast<unsigned>(v), d));
    }
    void sync() { warp->collective(lane, Op::sync, 0, 0); }
    void publish() { warp->collective(lane, Op::publish, 0, 0); }
  };

  // Runs body(lane) on all 32 lanes to their end; false if the lanes fell out of step.
  bool run(std::function<void(Lane&)> body) {
    body_ = std::move(body);
    current_ = this;
    for (int lane = 0; lane < k_warp_lanes; ++lane) {
      stacks_[lane].assign(256 * 1024, 0);
      getcontext(&lanes_[lane]);
      lanes_[lane].uc_stack.ss_sp = stacks_[lane].data();
      lanes_[lane].uc_stack.ss_size = stacks_[lane].size();
      lanes_[lane].uc_link = &scheduler_;
      makecontext(&lanes_[lane], reinterpret_cast<void (*)()>(&FiberWarp::start), 1, lane);
      done_[lane] = false;
    }
    for (;;) {
      for (int lane = 0; lane < k_warp_lanes; ++lane) {
        op_[lane] = Op::none;
        swapcontext(&scheduler_, &lanes_[lane]);
      }
      int finished = 0;
      for (int lane = 0; lane < k_warp_lanes; ++lane) finished += done_[lane];
      if (finished == k_warp_lanes) return true;
      if (finished != 0) return false; // some lanes left while others still call
      for (int lane = 1; lane < k_warp_lanes; ++lane)
        if (op_[lane] != op_[0]) return false;
      settle();
    }
  }

private:
  static void start(int lane) {
    FiberWarp* self = current_;
    Lane me{self, lane};
    self->body_(me);
    self->done_[lane] = true; // uc_link returns to the scheduler
  }

  unsigned collective(int lane, Op op, unsigned value, int argument) {
    op_[lane] = op;
    value_[lane] = value;
    argument_[lane] = argument;
    swapcontext(&lanes_[lane], &scheduler_);
    return result_[lane];
  }

  // Every lane waits in the same collective: its results.
  void settle() {
    unsigned mask = 0;
    for (int lane = 0; lane < k_warp_lanes; ++lane) mask |= (value_[lane] & 1u) << lane;
    for (int lane = 0; lane < k_warp_lanes; ++lane) {
      const int a = argument_[lane];
      switch (op_[lane]) {
      case Op::ballot:
        result_[lane] = mask;
        break;
      case Op::any:
        result_[lane] = mask != 0;
        break;
      case Op::shfl:
        result_[lane] = value_[a % k_warp_lanes];
        break;
      case Op::shfl_down:
        result_[lane] = lane + a < k_warp_lanes ? value_[lane + a] : value_[lane];
        break;
      case Op::shfl_up:
        result_[lane] = lane - a >= 0 ? value_[lane - a] : value_[lane];
        break;
      default:
        result_[lane] = 0;
      }
    }
  }

  static inline thread_local FiberWarp* current_ = nullptr;
  std::function<void(Lane&)> body_;
  ucontext_t scheduler_{};
  ucontext_t lanes_[k_warp_lanes]{};
  std::vector<char> stacks_[k_warp_lanes];
  bool done_[k_warp_lanes]{};
  Op op_[k_warp_lanes]{};
  unsigned value_[k_warp_lanes]{}, result_[k_warp_lanes]{};
  int argument_[k_warp_lanes]{};
};

// The arrays of one walk, started as hploc.cu's StartLeaves starts them, over sorted codes and
// leaf boxes made up for the test.
struct WalkArrays {
  std::vector<Aabb> boxes;
  std::vector<int> leaf_counts, parents, left_leaves, clusters;
  std::vector<unsigned long long> far_ends;
  std::vector<ClusterPair> nodes;
  int node_counter = 0;
  HplocWalk walk;
  WalkArrays(const std::vector<std::uint32_t>& codes, const std::vector<Aabb>& leaf_boxes,
             int radius, int threshold) {
    const int n = static_cast<int>(codes.size());
    boxes.assign(2 * n - 1, Aabb{});
    std::copy(leaf_boxes.begin(), leaf_boxes.end(), boxes.begin());
    leaf_counts.assign(2 * n - 1, 1);
    parents.assign(2 * n - 1, -1);
    left_leaves.assign(2 * n - 1, 0);
    far_ends.assign(n - 1, k_no_far_end);
    clusters.resize(n);
    for (int k = 0; k < n; ++k) clusters[k] = k;
    nodes.resize(n - 1);
    walk = {
        {n, boxes.data(), leaf_counts.data(), nodes.data(), parents.data(), left_leaves.data()},
        codes.data(),
        far_ends.data(),
        clusters.data(),
        &node_counter,
        radius,
        threshold};
  }
  // The tree as one walk from its root sees it, whatever numbers its nodes got: a leaf's
  // number, an interior node's leaf count and box bits, in depth-first order.
  std::vector<std::uint32_t> shape() const {
    const int n = walk.tree.n;
    int root = -1;
    for (int id = n; id < 2 * n - 1; ++id)
      if (parents[id] < 0) root = id;
    std::vector<std::uint32_t> out;
    std::vector<int> stack = {root};
    while (!stack.empty()) {
      const int id = stack.back();
      stack.pop_back();
      if (id < 0) {
        out.push_back(0xffffffffu);
        continue;
      }
      out.push_back(static_cast<std::uint32_t>(id < n ? id : leaf_counts[id] + n));
      if (id < n) continue;
      for (const float f : {boxes[id].lo.x, boxes[id].lo.y, boxes[id].lo.z, boxes[id].hi.x,
                            boxes[id].hi.y, boxes[id].hi.z})
        out.push_back(std::bit_cast<std::uint32_t>(f));
      stack.push_back(nodes[id - n].child[1]);
      stack.push_back(nodes[id - n].child[0]);
    }
    return out;
  }
};

// Sorted codes with runs of equal ones, and boxes scattered around points along them.
// Sorted codes (every seventh repeating the one before) and leaf boxes; with `ties`, boxes of
// three repeated shapes, so that merge costs tie and the leftmost-of-equals rule decides.
void made_up_leaves(int n, unsigned seed, std::vector<std::uint32_t>& codes,
                    std::vector<Aabb>& boxes, bool ties = false) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::uint32_t> code(0, (1u << 30) - 1);
  std::uniform_real_distribution<float> where(0.0f, 100.0f), size(0.01f, 3.0f);
  codes.resize(n);
  for (int k = 0; k < n; ++k) codes[k] = k % 7 == 3 ? codes[k - 1] : code(rng);
  std::sort(codes.begin(), codes.end());
  boxes.resize(n);
  for (int k = 0; k < n; ++k) {
    const Vec3f c{float(k) * 0.1f + where(rng) * 0.05f, where(rng), where(rng)};
    boxes[k] = Aabb{};
    if (ties) {
      boxes[k].grow(Vec3f{float(k % 3), 0.0f, 0.0f});
      boxes[k].grow(Vec3f{float(k % 3) + 1.0f, 1.0f, 1.0f});
      continue;
    }
    boxes[k].grow(c);
    boxes[k].grow(c + Vec3f{size(rng), size(rng), size(rng)});
  }
}

} // namespace

TEST_CASE("the n-th set bit of a lane mask, by binary search, is the counted one",
          "[ch10][hploc]") {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 2000; ++trial) {
    const unsigned mask = trial == 0   ? ~0u
                          : trial == 1 ? 1u << 31
                                       : static_cast<unsigned>(rng());
    int p = 0;
    for (int lane = 0; lane < k_warp_lanes; ++lane)
      if ((mask >> lane & 1u) != 0) CHECK(nth_set_bit(mask, p++) == lane);
    CHECK(p == count_bits(mask));
  }
}

TEST_CASE("one list's merge is a plain PLOC's on the same clusters", "[ch10][hploc]") {
  std::mt19937 rng(7);
  int compared = 0;
  for (const bool ties : {false, true})
    for (const int count : {2, 3, 17, 31, 32})
      for (const int target : {1, 8, k_hploc_threshold})
        for (const int radius : {1, 3, k_ploc_radius, k_warp_lanes - 1}) {
          if (target >= count) continue;
          CAPTURE(ties, count, target, radius);
          std::vector<Cluster> list = random_clusters(rng, count, ties);
          ClusterList lanes = to_lanes(list);
          RecordedNodes nodes;
          merge_cluster_list(lanes, target, radius, nodes);
          const std::vector<MadeNode> expected = plain_ploc(list, target, radius);
          CHECK(nodes.made == expected);
          CHECK(ids_of(lanes) == ids_of(list));
          CHECK(lanes.count <= target);
          CHECK(lanes.count >= 1);
          ++compared;
        }
  CHECK(compared > 80);
  // The test sees a tie-break: on boxes of three repeated shapes the rightmost of equal costs
  // merges other pairs than the leftmost.
  std::vector<Cluster> list = random_clusters(rng, 32, true);
  std::vector<Cluster> wrong = list;
  ClusterList lanes = to_lanes(list);
  RecordedNodes nodes;
  merge_cluster_list(lanes, 1, k_ploc_radius, nodes);
  CHECK(!(nodes.made == plain_ploc(wrong, 1, k_ploc_radius, true)));
  CHECK(nodes.made == plain_ploc(list, 1, k_ploc_radius));
}

TEST_CASE("the GPU's walk, its warps played by fibers, builds the CPU threads' tree",
          "[ch10][hploc]") {
  // walk_on_warp is the kernel's code; here each warp's 32 lanes run in lockstep as fibers,
  // the warps one after another in a scrambled order (a schedule a GPU may choose).
  // The cases with ties tell the warp's tie rule (nearest_on_warp) from the CPU's.
  struct Case {
    int n, radius, threshold;
    bool ties;
  };
  for (const Case c :
       {Case{700, k_ploc_radius, k_hploc_threshold, false}, Case{1500, 3, 8, false},
        Case{333, k_ploc_radius, 1, false}, Case{64, 31, k_hploc_threshold, false},
        Case{17, k_ploc_radius, k_hploc_threshold, false}, Case{2, 1, 1, false},
        Case{700, k_ploc_radius, k_hploc_threshold, true}, Case{300, 3, 8, true}}) {
    CAPTURE(c.n, c.radius, c.threshold, c.ties);
    std::vector<std::uint32_t> codes;
    std::vector<Aabb> boxes;
    made_up_leaves(c.n, 11 + c.n, codes, boxes, c.ties);
    WalkArrays on_cpu(codes, boxes, c.radius, c.threshold);
    for (int leaf = c.n - 1; leaf >= 0; --leaf) walk_on_cpu(on_cpu.walk, leaf);
    WalkArrays on_warps(codes, boxes, c.radius, c.threshold);
    FiberWarp warp;
    for (const int w : scrambled_warps(c.n, c.n))
      REQUIRE(warp.run([&](FiberWarp::Lane& lane) {
        walk_on_warp(lane, on_warps.walk, w * k_warp_lanes + lane.lane, lane.lane);
      }));
    CHECK(on_cpu.node_counter == c.n - 1);
    CHECK(on_warps.node_counter == c.n - 1);
    CHECK(on_warps.shape() == on_cpu.shape());
  }
  // And the comparison sees a difference: another threshold, another tree.
  std::vector<std::uint32_t> codes;
  std::vector<Aabb> boxes;
  made_up_leaves(700, 5, codes, boxes);
  WalkArrays sixteen(codes, boxes, k_ploc_radius, k_hploc_threshold);
  WalkArrays eight(codes, boxes, k_ploc_radius, 8);
  for (int leaf = 0; leaf < 700; ++leaf) {
    walk_on_cpu(sixteen.walk, leaf);
    walk_on_cpu(eight.walk, leaf);
  }
  CHECK(sixteen.shape() != eight.shape());
}

TEST_CASE("H-PLOC trees pass chapter 07's checker and give brute force's hits",
          "[ch10][hploc]") {
  for (const Vec3f centre : {Vec3f{}, Vec3f{-1e5f, 2e4f, 1e5f}}) {
    CAPTURE(centre.x);
    Mesh mesh = rt::testing::mixed_scene(3000, 13);
    for (Vec3f& v : mesh.vertices) v = v + centre;
    const GpuBuild hploc = build_hploc(Backend::cpu, mesh);
    CHECK(ch07::check_bvh(hploc.bvh, mesh).empty());
    CHECK(hploc.note.empty());
    CHECK(hploc.bvh.stats.leaves == static_cast<int>(mesh.triangles.size()));
    CHECK(hploc.bvh.options.max_leaf_size == 1);
    const auto rays = rt::testing::random_rays(3000, 19, centre, 10.0f);
    CHECK(brute_force_mismatches(hploc.bvh.view(), mesh, rays) == 0);
    // The boxes the merges made are the ones the bottom-up pass gives the tree, bit for bit.
    ch07::Bvh refitted = hploc.bvh;
    refit_bvh(Backend::cpu, refitted, mesh);
    CHECK(same_tree(refitted, hploc.bvh));
    CHECK(rt::testing::same_bits(refitted.bounds, hploc.bvh.bounds));
  }
}

TEST_CASE("the CPU threads build the same H-PLOC tree every time", "[ch10][hploc]") {
  // Node numbers come from an atomic counter in whatever order the threads reach it; the
  // tree laid out depth first does not depend on them.
  const Mesh mesh = rt::testing::random_soup(20000, 17);
  const GpuBuild a = build_hploc(Backend::cpu, mesh);
  for (int run = 0; run < 3; ++run)
    CHECK(same_tree(build_hploc(Backend::cpu, mesh).bvh, a.bvh));
}

TEST_CASE("H-PLOC's SAH cost is near PLOC's and below the LBVH's", "[ch10][hploc]") {
  // Measured: H-PLOC 89.9 and 88.8, PLOC 89.5 and 88.8, the LBVH 95.4 and 94.9.
  for (const unsigned seed : {23u, 29u}) {
    CAPTURE(seed);
    const Mesh mesh = rt::testing::mixed_scene(6000, seed);
    const double hploc = build_hploc(Backend::cpu, mesh).bvh.stats.sah_cost;
    const double ploc = build_ploc(Backend::cpu, mesh).bvh.stats.sah_cost;
    const double lbvh = build_lbvh(Backend::cpu, mesh, CodeWidth::bits30).bvh.stats.sah_cost;
    CAPTURE(hploc, ploc, lbvh);
    CHECK(hploc < 1.01 * ploc);
    CHECK(hploc < 0.96 * lbvh);
  }
}

TEST_CASE("a threshold of one is the LBVH, other thresholds and radii other trees",
          "[ch10][hploc]") {
  const Mesh mesh = rt::testing::mixed_scene(4000, 31);
  // Every node merges its children's single clusters as they come, left and right.
  const GpuBuild one = build_hploc(Backend::cpu, mesh, k_ploc_radius, 1);
  const GpuBuild lbvh = build_lbvh(Backend::cpu, mesh, CodeWidth::bits30);
  CHECK(same_tree(one.bvh, lbvh.bvh));
  // Equal codes too, split by the leaves' numbers (karras.h's delta), on the way up as down.
  for (const Mesh& tied : {identical_triangles(1000), power_of_two_chain(300)})
    CHECK(same_tree(build_hploc(Backend::cpu, tied, k_ploc_radius, 1).bvh,
                    build_lbvh(Backend::cpu, tied, CodeWidth::bits30).bvh));
  const GpuBuild full = build_hploc(Backend::cpu, mesh);
  const GpuBuild half = build_hploc(Backend::cpu, mesh, k_ploc_radius, 8);
  const GpuBuild near = build_hploc(Backend::cpu, mesh, 1);
  for (const GpuBuild* other : {&one, &half, &near}) {
    CHECK(ch07::check_bvh(other->bvh, mesh).empty());
    CHECK(!same_tree(other->bvh, full.bvh));
  }
  // Lists to choose from beat the LBVH's splits (not always the longer the better: measured
  // 71.5 at 16, 70.6 at 8, 76.7 at 1).
  CHECK(full.bvh.stats.sah_cost < 0.96 * one.bvh.stats.sah_cost);
  CHECK(half.bvh.stats.sah_cost < 0.96 * one.bvh.stats.sah_cost);
}

TEST_CASE("degenerate input: within the depth bound, or the LBVH with a note",
          "[ch10][hploc]") {
  struct Case {
    const char* name;
    Mesh mesh;
  };
  const Case cases[] = {
      {"two triangles", identical_triangles(2)},
      {"three triangles", identical_triangles(3)},
      {"seventeen identical", identical_triangles(17)},
      {"4096 identical", identical_triangles(4096)},
      {"200 000 identical", identical_triangles(200000)},
      {"powers of two", power_of_two_chain(4096)},
      {"collinear", collinear_triangles(100000)},
      {"ever wider spaced", exponentially_spaced_triangles(480)},
      {"huge coordinates", huge_soup()},
  };
  int fell_back = 0;
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const GpuBuild hploc = build_hploc(Backend::cpu, c.mesh);
    CHECK(ch07::check_bvh(hploc.bvh, c.mesh).empty());
    CHECK(hploc.bvh.stats.depth <= ch07::k_max_bvh_depth - 1);
    if (!hploc.note.empty()) {
      ++fell_back;
      CHECK(same_tree(hploc.bvh, build_lbvh(Backend::cpu, c.mesh, CodeWidth::bits30).bvh));
    }
  }
  // Identical boxes tie everywhere: the leftmost pair merges, one a step, and the list's first
  // cluster swallows the rest, a chain that grows at every level above; the LBVH takes over.
  const GpuBuild identical = build_hploc(Backend::cpu, identical_triangles(4096));
  CHECK(!identical.note.empty());
  CHECK(fell_back >= 1);
  // The smallest inputs keep H-PLOC's tree.
  CHECK(build_hploc(Backend::cpu, identical_triangles(3)).note.empty());
  for (const Mesh& mesh : {rt::testing::single_triangle(), Mesh{}}) {
    const GpuBuild tiny = build_hploc(Backend::cpu, mesh);
    CHECK(ch07::check_bvh(tiny.bvh, mesh).empty());
  }
}

TEST_CASE("no ray leaks out of a closed mesh through H-PLOC's tree", "[ch10][hploc]") {
  for (const ch04::LeakConfiguration& config : ch04::k_leak_configurations) {
    CAPTURE(config.name);
    const Mesh mesh = config.make_mesh();
    const std::vector<RayF> rays = ch04::rays_at_vertices_and_edges(
        mesh, config.inside(), config.spread, 20000, config.seed);
    const ch07::Bvh tree = build_hploc(Backend::cpu, mesh).bvh;
    CHECK(ch07::check_bvh(tree, mesh).empty());
    int leaks = 0, any_leaks = 0;
    for (const RayF& ray : rays) {
      leaks += ch07::trace_bvh<ch07::Query::closest, ch04::TriangleVariant::watertight>(
                   tree.view(), ray)
                   .triangle < 0;
      any_leaks +=
          ch07::trace_bvh<ch07::Query::any, ch04::TriangleVariant::watertight>(tree.view(), ray)
              .triangle < 0;
    }
    CHECK(leaks == 0);
    CHECK(any_leaks == 0);
  }
}

TEST_CASE("H-PLOC refuses bad input with one line", "[ch10][hploc]") {
  Mesh nan_vertex = rt::testing::random_soup(100, 3);
  nan_vertex.vertices[57].y = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH(build_hploc(Backend::cpu, nan_vertex),
                    Catch::Matchers::Contains("triangle 19: vertex 57 is not finite"));
  const Mesh mesh = identical_triangles(4);
  CHECK_THROWS_WITH(build_hploc(Backend::cpu, mesh, 0),
                    Catch::Matchers::Contains("H-PLOC radius 0: it takes 1 to 31"));
  CHECK_THROWS_AS(build_hploc(Backend::cpu, mesh, k_warp_lanes), InputError);
  CHECK_THROWS_WITH(build_hploc(Backend::cpu, mesh, k_ploc_radius, 0),
                    Catch::Matchers::Contains("H-PLOC threshold 0: it takes 1 to 16"));
  CHECK_THROWS_AS(build_hploc(Backend::cpu, mesh, k_ploc_radius, k_hploc_threshold + 1),
                  InputError);
}

TEST_CASE("the GPU's H-PLOC tree is the CPU's, bit for bit", "[ch10][hploc][gpu]") {
  RT_REQUIRE_GPU();
  struct Case {
    Mesh mesh;
    int threshold;
  };
  // Many warps: the scenes of 20 000 and 300 000 triangles run thousands of them, their
  // merges racing for node numbers.
  const std::vector<Case> cases = {
      {rt::testing::mixed_scene(20000, 41), k_hploc_threshold},
      {rt::testing::random_soup(300000, 43, Vec3f{1e5f, 0.0f, -3e4f}), k_hploc_threshold},
      {rt::testing::mixed_scene(20000, 41), 8},
      {rt::testing::mixed_scene(20000, 41), 1},
      {identical_triangles(3000), k_hploc_threshold},
      {identical_triangles(17), k_hploc_threshold},
      {power_of_two_chain(4096), k_hploc_threshold},
      {collinear_triangles(100000), k_hploc_threshold},
      {huge_soup(), k_hploc_threshold},
      {rt::testing::single_triangle(), k_hploc_threshold},
  };
  for (const Case& c : cases) {
    CAPTURE(c.mesh.triangles.size(), c.threshold);
    const GpuBuild gpu = build_hploc(Backend::gpu, c.mesh, k_ploc_radius, c.threshold);
    const GpuBuild cpu = build_hploc(Backend::cpu, c.mesh, k_ploc_radius, c.threshold);
    CHECK(ch07::check_bvh(gpu.bvh, c.mesh).empty());
    CHECK(same_tree(gpu.bvh, cpu.bvh));
    CHECK(rt::testing::same_bits(gpu.bvh.bounds, cpu.bvh.bounds));
    CHECK(gpu.note == cpu.note);
    // And again: another run, other node numbers, the same tree.
    CHECK(
        same_tree(build_hploc(Backend::gpu, c.mesh, k_ploc_radius, c.threshold).bvh, gpu.bvh));
  }
}

TEST_CASE("the GPU's collapse of H-PLOC's tree is the CPU's", "[ch10][hploc][gpu]") {
  RT_REQUIRE_GPU();
  const Mesh mesh = rt::testing::mixed_scene(20000, 73);
  const ch07::Bvh binary = build_hploc(Backend::gpu, mesh).bvh;
  const ch09::Wide4PackedBvh gpu = collapse_to_wide4(Backend::gpu, binary);
  const ch09::Wide4PackedBvh cpu = collapse_to_wide4(Backend::cpu, binary);
  CHECK(ch09::check_wide_tree(gpu, mesh).empty());
  CHECK(rt::testing::same_bits(gpu.nodes, cpu.nodes));
  CHECK(rt::testing::same_bits(gpu.triangles, cpu.triangles));
}

// --- Treelet restructuring (treelets.h) ---

namespace {

// The least total area of the interior nodes of any binary tree over `boxes`, found by making
// every tree: leaf k joins a tree over leaves 0 .. k-1 above any of its nodes (as the sibling
// of that node, under a new parent), which makes each of the 1 * 3 * 5 * ... * (2k - 3) trees
// once. A tree is kept as a list of interior nodes, each the set of leaves below it.
double least_area_by_every_tree(const std::vector<Aabb>& boxes) {
  struct Tree {
    std::vector<unsigned> sets; // interior nodes' leaves
    std::vector<unsigned> all;  // every node's leaves: interior and leaves
  };
  std::vector<Tree> trees = {{{}, {1u}}};
  for (int k = 1; k < static_cast<int>(boxes.size()); ++k) {
    std::vector<Tree> next;
    for (const Tree& tree : trees)
      for (const unsigned below : tree.all) {
        // The new parent holds `below` and leaf k; every node above `below` gains leaf k.
        Tree grown;
        for (const unsigned set : tree.sets)
          grown.sets.push_back((set & below) == below && set != below ? set | 1u << k : set);
        grown.sets.push_back(below | 1u << k);
        grown.all = grown.sets;
        for (int leaf = 0; leaf <= k; ++leaf) grown.all.push_back(1u << leaf);
        next.push_back(std::move(grown));
      }
    trees = std::move(next);
  }
  double least = std::numeric_limits<double>::infinity();
  for (const Tree& tree : trees) {
    double area = 0.0;
    for (const unsigned set : tree.sets) {
      Aabb box;
      for (int leaf = 0; leaf < static_cast<int>(boxes.size()); ++leaf)
        if ((set >> leaf & 1u) != 0) box.grow(boxes[leaf]);
      area += box.half_area();
    }
    least = std::min(least, area);
  }
  return least;
}

// A treelet whose leaves are `boxes` (leaves of the tree too), in any shape: the search only
// reads its leaves.
Treelet treelet_of(const std::vector<Aabb>& boxes) {
  Treelet t;
  t.leaf_count = static_cast<int>(boxes.size());
  for (int i = 0; i < t.leaf_count; ++i) {
    t.leaf[i] = i;
    t.box[i] = boxes[i];
  }
  return t;
}

// The total area of the interior nodes of the tree split[] describes over `set`.
double area_of_searched_tree(const Treelet& t, const TreeletSearch& s, unsigned set) {
  if ((set & (set - 1u)) == 0) return 0.0;
  return double(subset_area(t, set)) + area_of_searched_tree(t, s, s.split[set]) +
         area_of_searched_tree(t, s, set ^ s.split[set]);
}

std::vector<Aabb> random_boxes(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> at(-10.0f, 10.0f), size(0.01f, 3.0f);
  std::vector<Aabb> boxes(count);
  for (Aabb& box : boxes) {
    box.lo = {at(rng), at(rng), at(rng)};
    box.hi = box.lo + Vec3f{size(rng), size(rng), size(rng)};
  }
  return boxes;
}

} // namespace

TEST_CASE("the treelet search finds the cheapest tree that making every tree finds",
          "[ch10][treelets]") {
  for (int count = 2; count <= k_treelet_leaves; ++count)
    for (unsigned seed = 0; seed < 12; ++seed) {
      CAPTURE(count, seed);
      const std::vector<Aabb> boxes = random_boxes(count, 100 * count + seed);
      const Treelet t = treelet_of(boxes);
      TreeletSearch s;
      search_treelet(t, s);
      const unsigned all = (1u << count) - 1u;
      const double least = least_area_by_every_tree(boxes);
      CHECK(s.cost[all] == Approx(least).epsilon(1e-6));
      CHECK(area_of_searched_tree(t, s, all) == Approx(least).epsilon(1e-6));
    }
}

TEST_CASE("a treelet in the worst shape is rewired into the best one", "[ch10][treelets]") {
  // Seven unit boxes on a line, merged as a chain from the left (each node the previous one
  // and the next box): the worst tree over them. The best is balanced.
  const int n = k_treelet_leaves;
  std::vector<Aabb> boxes(2 * n - 1);
  std::vector<int> leaf_counts(2 * n - 1, 1), parents(2 * n - 1, -1), left_leaves(2 * n - 1, 0);
  std::vector<ClusterPair> nodes(n - 1);
  for (int k = 0; k < n; ++k) {
    boxes[k].lo = {float(3 * k), 0.0f, 0.0f};
    boxes[k].hi = {float(3 * k + 1), 1.0f, 1.0f};
  }
  const ClusterTree tree{
      n, boxes.data(), leaf_counts.data(), nodes.data(), parents.data(), left_leaves.data()};
  // Interior node j (number n + j) joins node n + j + 1 (or leaf n - 2) with leaf n - 1 - j:
  // the root n + 0 at the top.
  for (int j = n - 2; j >= 0; --j) {
    const int left = j == n - 2 ? 0 : n + j + 1, right = n - 1 - j;
    Aabb box = boxes[left];
    box.grow(boxes[right]);
    boxes[n + j] = box;
    leaf_counts[n + j] = leaf_counts[left] + 1;
    link_children(tree, j, left, right, leaf_counts[left]);
  }
  const Aabb root_box = boxes[n];
  auto interior_area = [&] {
    double area = 0.0;
    for (int j = 0; j < n - 1; ++j) area += boxes[n + j].half_area();
    return area;
  };
  const double before = interior_area();
  REQUIRE(restructure_treelet(tree, n));
  CHECK(interior_area() < before);
  CHECK(interior_area() ==
        Approx(least_area_by_every_tree({boxes.begin(), boxes.begin() + n})));
  // Still one tree over the seven leaves: links both ways, counts and boxes of the children.
  CHECK(rt::testing::same_bits(boxes[n], root_box));
  CHECK(parents[n] == -1);
  std::vector<int> seen(2 * n - 1, 0);
  for (int j = 0; j < n - 1; ++j) {
    Aabb box;
    int leaves = 0;
    for (int c = 0; c < 2; ++c) {
      const int child = nodes[j].child[c];
      ++seen[child];
      CHECK(parents[child] == 2 * j + c);
      box.grow(boxes[child]);
      leaves += leaf_counts[child];
    }
    CHECK(left_leaves[nodes[j].child[1]] == leaf_counts[nodes[j].child[0]]);
    CHECK(rt::testing::same_bits(box, boxes[n + j]));
    CHECK(leaves == leaf_counts[n + j]);
  }
  CHECK(seen[n] == 0);
  for (int x = 0; x < 2 * n - 1; ++x)
    if (x != n) CHECK(seen[x] == 1);
  // The best shape is kept: a second pass finds nothing cheaper.
  CHECK(!restructure_treelet(tree, n));
}

TEST_CASE("the GPU's treelet walk, its warps played by fibers, makes the CPU threads' tree",
          "[ch10][treelets]") {
  // restructure_on_warp is the kernel's code: each treelet searched by a whole warp, the
  // lanes in lockstep as fibers, the warps one after another in a scrambled order.
  for (const int n : {1500, 700, 45, 9, 2}) {
    CAPTURE(n);
    std::vector<std::uint32_t> codes;
    std::vector<Aabb> boxes;
    made_up_leaves(n, 3 + n, codes, boxes);
    WalkArrays on_cpu(codes, boxes, k_ploc_radius, k_hploc_threshold);
    WalkArrays on_warps(codes, boxes, k_ploc_radius, k_hploc_threshold);
    for (int leaf = 0; leaf < n; ++leaf) {
      walk_on_cpu(on_cpu.walk, leaf);
      walk_on_cpu(on_warps.walk, leaf);
    }
    const std::vector<std::uint32_t> before = on_cpu.shape();
    for (int round = 0; round < k_treelet_rounds; ++round) {
      std::vector<unsigned> cpu_arrivals(n - 1, 0u), warp_arrivals(n - 1, 0u);
      const RestructureTreelets threads{on_cpu.walk.tree, cpu_arrivals.data(),
                                        treelet_min_leaves(round)};
      for (int leaf = n - 1; leaf >= 0; --leaf) threads(leaf);
      const RestructureTreelets warps{on_warps.walk.tree, warp_arrivals.data(),
                                      treelet_min_leaves(round)};
      FiberWarp warp;
      TreeletTables tables;
      for (const int w : scrambled_warps(n, n + round))
        REQUIRE(warp.run([&](FiberWarp::Lane& lane) {
          restructure_on_warp(lane, warps, w * k_warp_lanes + lane.lane, lane.lane, tables);
        }));
      CHECK(on_warps.shape() == on_cpu.shape());
    }
    // The rounds did something, where there was room: seven leaves make a treelet.
    if (n >= 45) CHECK(on_cpu.shape() != before);
  }
}

TEST_CASE("treelet rounds make H-PLOC's tree cheaper, and keep it whole and exact",
          "[ch10][treelets]") {
  for (const Vec3f centre : {Vec3f{}, Vec3f{-1e5f, 2e4f, 1e5f}}) {
    CAPTURE(centre.x);
    Mesh mesh = rt::testing::mixed_scene(6000, 37);
    for (Vec3f& v : mesh.vertices) v = v + centre;
    const GpuBuild plain = build_hploc(Backend::cpu, mesh);
    double cost = plain.bvh.stats.sah_cost;
    for (int rounds = 1; rounds <= 3; ++rounds) {
      CAPTURE(rounds);
      const GpuBuild better =
          build_hploc(Backend::cpu, mesh, k_ploc_radius, k_hploc_threshold, rounds);
      CHECK(better.note.empty());
      CHECK(ch07::check_bvh(better.bvh, mesh).empty());
      // Never worse, round after round; the first round does the most.
      CHECK(better.bvh.stats.sah_cost <= cost);
      if (rounds == 1) CHECK(better.bvh.stats.sah_cost < 0.99 * cost);
      cost = better.bvh.stats.sah_cost;
      const auto rays = rt::testing::random_rays(2000, 23, centre, 10.0f);
      CHECK(brute_force_mismatches(better.bvh.view(), mesh, rays) == 0);
      ch07::Bvh refitted = better.bvh;
      refit_bvh(Backend::cpu, refitted, mesh);
      CHECK(same_tree(refitted, better.bvh));
    }
  }
}

TEST_CASE("the CPU threads restructure H-PLOC's tree the same way every time",
          "[ch10][treelets]") {
  const Mesh mesh = rt::testing::random_soup(20000, 47);
  const GpuBuild a = build_hploc(Backend::cpu, mesh, k_ploc_radius, k_hploc_threshold, 2);
  for (int run = 0; run < 3; ++run)
    CHECK(same_tree(build_hploc(Backend::cpu, mesh, k_ploc_radius, k_hploc_threshold, 2).bvh,
                    a.bvh));
}

TEST_CASE("restructured trees: no leaks, degenerate input, bad rounds refused",
          "[ch10][treelets]") {
  for (const ch04::LeakConfiguration& config : ch04::k_leak_configurations) {
    CAPTURE(config.name);
    const Mesh mesh = config.make_mesh();
    const std::vector<RayF> rays = ch04::rays_at_vertices_and_edges(
        mesh, config.inside(), config.spread, 20000, config.seed);
    const ch07::Bvh tree =
        build_hploc(Backend::cpu, mesh, k_ploc_radius, k_hploc_threshold, k_treelet_rounds).bvh;
    CHECK(ch07::check_bvh(tree, mesh).empty());
    int leaks = 0;
    for (const RayF& ray : rays)
      leaks += ch07::trace_bvh<ch07::Query::closest, ch04::TriangleVariant::watertight>(
                   tree.view(), ray)
                   .triangle < 0;
    CHECK(leaks == 0);
  }
  // Areas of infinity and NaN (huge coordinates), every box equal, chains: whole trees.
  for (const Mesh& mesh : {huge_soup(), identical_triangles(3), identical_triangles(500),
                           power_of_two_chain(300), collinear_triangles(5000)}) {
    CAPTURE(mesh.triangles.size());
    const GpuBuild built =
        build_hploc(Backend::cpu, mesh, k_ploc_radius, k_hploc_threshold, k_treelet_rounds);
    CHECK(ch07::check_bvh(built.bvh, mesh).empty());
    CHECK(built.bvh.stats.depth <= ch07::k_max_bvh_depth - 1);
  }
  const Mesh mesh = identical_triangles(4);
  CHECK_THROWS_WITH(build_hploc(Backend::cpu, mesh, k_ploc_radius, k_hploc_threshold, -1),
                    Catch::Matchers::Contains("treelet rounds -1: it takes 0 to 8"));
  CHECK_THROWS_AS(build_hploc(Backend::cpu, mesh, k_ploc_radius, k_hploc_threshold,
                              k_max_treelet_rounds + 1),
                  InputError);
}

TEST_CASE("the GPU restructures H-PLOC's tree as the CPU does, bit for bit",
          "[ch10][treelets][gpu]") {
  RT_REQUIRE_GPU();
  for (const Mesh& mesh :
       {rt::testing::mixed_scene(20000, 41), rt::testing::random_soup(300000, 43), huge_soup(),
        identical_triangles(3000), collinear_triangles(100000)}) {
    CAPTURE(mesh.triangles.size());
    const GpuBuild gpu =
        build_hploc(Backend::gpu, mesh, k_ploc_radius, k_hploc_threshold, k_treelet_rounds);
    const GpuBuild cpu =
        build_hploc(Backend::cpu, mesh, k_ploc_radius, k_hploc_threshold, k_treelet_rounds);
    CHECK(ch07::check_bvh(gpu.bvh, mesh).empty());
    CHECK(same_tree(gpu.bvh, cpu.bvh));
    CHECK(gpu.note == cpu.note);
  }
}
