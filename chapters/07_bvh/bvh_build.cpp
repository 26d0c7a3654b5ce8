// Chapter 07: the BVH build, object median and binned SAH, and the checker that every test of
// the chapter runs on its trees. See bvh_build.h.
#include "bvh_build.h"

#include <algorithm>
#include <atomic>
#include <barrier>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "rt/backend.h"
#include "rt/cpu_progress.h"
#include "rt/error.h"
#include "rt/launch.h"
#include "sbvh_build.h"

namespace rt::ch07 {

const char* to_string(SplitMethod method) {
  switch (method) {
  case SplitMethod::median:
    return "median";
  case SplitMethod::sah:
    return "sah";
  case SplitMethod::sbvh:
    return "sbvh";
  }
  return "unknown";
}

namespace {

constexpr int k_max_bins = 256;

// The chance that a ray through the parent box also enters the child box. A flat or
// point-like parent has no area to divide by; a ray that touches it touches the child too.
double area_ratio(double child_area, double parent_area) {
  return parent_area > 0.0 ? child_area / parent_area : 1.0;
}

Aabb join(Aabb a, const Aabb& b) {
  a.grow(b);
  return a;
}

// [listing:depth_bound]
// The depth bound, proved by induction. Let D = k_max_bvh_depth - 1, L = max_leaf_size and
// levels(m) = halving_levels(m, L). Every node the build makes, at depth d with n triangles
// below it, keeps the invariant  d + levels(n) <= D.
//  - The root: d = 0 and n <= 1 << 28, so levels(n) <= 28 <= D.
//  - A median split happens only when n > L; its children hold floor(n/2) and ceil(n/2)
//    triangles at depth d + 1, and levels(n) = 1 + levels(ceil(n/2)), so both children keep
//    d + 1 + levels(ceil(n/2)) = d + levels(n) <= D (levels never decreases with m).
//  - An SAH split is accepted only when the test below holds, which is the invariant for its
//    larger child, and so for both.
// So no interior node lies deeper than D - 1 (one with n > L has levels(n) >= 1, one split by
// the SAH passed the test, so d + 1 <= D): within the bound D, with a level to spare. A
// traversal stack of k_max_bvh_depth entries never overflows, whatever the mesh. And since the
// median split keeps the invariant by itself, a node with more than L triangles can always be
// split.
bool within_depth_bound(int depth, int left_count, int right_count, int max_leaf_size) {
  const int larger = std::max(left_count, right_count);
  return depth + 1 + halving_levels(larger, max_leaf_size) <= k_max_bvh_depth - 1;
}
// [/listing:depth_bound]

// The two children of the references [begin, end): the left one holds [begin, mid), the right
// one [mid, end).
struct Split {
  int mid = 0;
  Aabb left, right; // exact bounds of each child's triangles
};

// What the build sorts: a triangle's number with its box and the centre of the box, computed
// once. Partitioning these in place (rather than bare numbers) moves the boxes along, so every
// pass over a node reads consecutive memory instead of gathering from all over the mesh.
struct Reference {
  Aabb box;
  Vec3f centroid;
  int id; // the mesh's number of the triangle
};

// [listing:sah_bin]
// A bin: the bounds of the triangles whose centroid falls in it, and how many there are. The
// bounds are kept as two rows of four floats, the fourth unused, so that on an x86 CPU a
// triangle's box joins them with one vector min and one vector max (grow_bin) where Aabb::grow
// takes six scalar ones, each a load and a store of the bin: binning is most of a build's time,
// and consecutive triangles, neighbours in space, mostly land in the same bins, each waiting
// for the last one's stores. The results are Aabb::grow's bit for bit: min_of(bin, t) is
// "t < bin ? t : bin", which is what the vector min of (t, bin) computes, max likewise.
struct alignas(16) Bin {
  float lo[4] = {k_inf, k_inf, k_inf, k_inf};
  float hi[4] = {-k_inf, -k_inf, -k_inf, -k_inf};
  int count = 0;
  Aabb box() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
  void grow(const Aabb& b) { // another bin's bounds: the merge of the threads' bins
    const Aabb joined = join(box(), b);
    for (int k = 0; k < 3; ++k) {
      lo[k] = joined.lo[k];
      hi[k] = joined.hi[k];
    }
  }
  static constexpr float k_inf = std::numeric_limits<float>::infinity();
};

// Triangle r's box into a bin.
inline void grow_bin(Bin& bin, const Reference& r) {
#if defined(__SSE__)
  // A reference's box is lo.xyz, hi.xyz and then its centroid: the four floats from lo.x and
  // the four from hi.x both lie within it.
  static_assert(offsetof(Reference, box) == 0 &&
                offsetof(Reference, centroid) == sizeof(Aabb) &&
                sizeof(Aabb) == 6 * sizeof(float));
  const __m128 lo = _mm_loadu_ps(&r.box.lo.x);
  const __m128 hi = _mm_loadu_ps(&r.box.hi.x);
  _mm_store_ps(bin.lo, _mm_min_ps(lo, _mm_load_ps(bin.lo)));
  _mm_store_ps(bin.hi, _mm_max_ps(hi, _mm_load_ps(bin.hi)));
#else
  bin.grow(r.box);
#endif
}
// [/listing:sah_bin]

// The best SAH plane found: between bins plane - 1 and plane along `axis`.
struct SahPlane {
  int axis = -1; // -1: no plane splits this range
  int plane = 0;
  double cost = std::numeric_limits<double>::infinity();
};

// [listing:hoare_partition]
// Hoare's partition of [begin, end): moves the references for which goes_left holds before the
// others, and returns where the others begin. A scan from the left stops at a reference that
// belongs on the right, one from the right stops at a reference that belongs on the left, the
// two trade places, and the scans go on until they meet. So the k-th reference from the left
// that belongs on the right trades places with the k-th from the right that belongs on the
// left, and nothing else moves: the outcome is fixed by the data alone, which lets a team of
// threads compute the very same one in slices (partition_shared below). std::partition promises
// no particular order, so the build does not lean on one library's choice.
template <class GoesLeft>
int partition_references(Reference* refs, int begin, int end, GoesLeft goes_left) {
  int first = begin, last = end;
  for (;;) {
    while (first < last && goes_left(refs[first])) ++first;
    if (first == last) return first;
    --last;
    while (first < last && !goes_left(refs[last])) --last;
    if (first == last) return first;
    std::swap(refs[first], refs[last]);
    ++first;
  }
}
// [/listing:hoare_partition]

// A fixed team of threads that run one function together, again and again: the calling thread
// is member 0, the others wait at a barrier between jobs. Starting threads for every pass of
// every node would cost more than the passes over the smaller nodes.
class ThreadTeam {
public:
  explicit ThreadTeam(int size) : size_(size), start_(size), finish_(size) {
    for (int t = 1; t < size; ++t) {
      members_.emplace_back([this, t] {
        for (;;) {
          start_.arrive_and_wait();
          if (stop_) return;
          (*job_)(t);
          finish_.arrive_and_wait();
        }
      });
    }
  }
  ~ThreadTeam() {
    stop_ = true;
    start_.arrive_and_wait(); // the members see stop_ and return; the jthreads join
  }
  ThreadTeam(const ThreadTeam&) = delete;
  ThreadTeam& operator=(const ThreadTeam&) = delete;

  int size() const { return size_; }

  // job(t) on every member t = 0 .. size() - 1; returns when all are done.
  template <class Job> void run(Job job) {
    const std::function<void(int)> f = job;
    job_ = &f;
    start_.arrive_and_wait();
    f(0);
    finish_.arrive_and_wait();
  }

  // Member t's slice of [begin, end), cut into size() nearly equal slices: both ends, for a
  // loop to keep in variables of its own. A loop that worked its end out in its test would
  // divide at every step: it stores through pointers, and for all the compiler knows a store
  // changes size_.
  struct Slice {
    int begin, end;
  };
  Slice slice(int begin, int end, int t) const {
    const auto cut = [&](int k) {
      return begin + static_cast<int>(static_cast<long long>(end - begin) * k / size_);
    };
    return {cut(t), cut(t + 1)};
  }

private:
  int size_;
  std::barrier<> start_, finish_;
  const std::function<void(int)>* job_ = nullptr;
  bool stop_ = false; // written before the start barrier, read after it
  std::vector<std::jthread> members_;
};

// Nodes this small take one thread for every pass: a pass over them is too short to share.
constexpr int k_min_shared_pass = 4096;
// How many subtrees each thread gets, about: a handful, since the SAH splits unevenly and the
// threads must finish together, but not many, since every level of the top costs passes that
// two threads share less well than whole subtrees (measured on the benchmark scenes: 4 builds
// faster than 8 or 16 on 2 threads, and as fast as 2).
constexpr int k_subtrees_per_thread = 4;
// Subtrees smaller than this are not handed out on their own: their parents' passes share well.
constexpr int k_min_subtree = 2048;
// How many triangles a thread places in leaves between reports to the progress count.
constexpr int k_progress_step = 4096;

// A piece of the tree as one thread writes it: its nodes, numbered from 0 in its own depth
// first order, and the counts of its nodes and leaves.
struct Fragment {
  std::vector<BvhNode> nodes;
  BuildStats stats;
};

// A subtree left for the second phase of the build: its root's split is made (its references
// are partitioned), its nodes are not. `position` is how many nodes the top of the tree had
// when it was handed out: in the serial depth-first order, the subtree comes right there.
struct Subtree {
  Split split;
  int begin = 0, end = 0, depth = 0;
  int position = 0;
  Fragment fragment;
  int start = 0; // its root's index in the whole tree, once known
};

// Building on every core. The tree must be the same for any number of threads, bit for bit, so
// every decision is taken exactly as the one-thread build takes it, on the same data:
//  - Top phase: the nodes with many triangles are split one after the other, as in the serial
//    build, but each pass over a node's references is shared by the team. Binning gives each
//    thread its own bins, then merges them: a bin's box is a min and a max and its count a
//    sum, so any merge order gives the same bins. The partition is Hoare's, whose outcome is
//    fixed by the data alone (see partition_references), so it can be computed in slices.
//  - A child of at most `handoff` triangles, once split, is not descended into: it becomes a
//    Subtree, a disjoint range of the references.
//  - Second phase: the threads take the subtrees, largest first, and build each one alone into
//    its own node array, with the serial code.
//  - Splice: every subtree's array is copied to the place it would have had in the serial
//    depth-first order, its node numbers shifted by where it starts.
// With one thread there is no top phase, and the build is the serial one.
class Builder {
public:
  Builder(const ch04::Mesh& mesh, const BuildOptions& options, int threads)
      : options_(options),
        progress_(static_cast<long long>(mesh.triangles.size()), "triangles in leaves") {
    const int n = static_cast<int>(mesh.triangles.size());
    if (threads > 1 && n >= 2 * k_min_subtree) team_.emplace(threads);
    references_.resize(n);
    const auto make_references = [&](int t) {
      const auto [begin, end] = team_ ? team_->slice(0, n, t) : ThreadTeam::Slice{0, n};
      for (int i = begin; i < end; ++i) { // check_build_input has vouched for every vertex
        Reference& r = references_[i];
        r.box = bounds_of(mesh.triangle(i));
        // Half of each end, not (v0 + v1 + v2) / 3 and not (lo + hi) / 2: both of those add
        // first, and the sum overflows to infinity for coordinates beyond half the largest
        // float.
        r.centroid = 0.5f * r.box.lo + 0.5f * r.box.hi;
        r.id = i;
      }
    };
    if (team_) {
      team_->run(make_references);
    } else {
      make_references(0);
    }
  }

  // Builds the nodes, and leaves the references in leaf order.
  void build(Bvh& bvh) {
    const int n = static_cast<int>(references_.size());
    const int handoff =
        team_ ? std::max(k_min_subtree, n / (k_subtrees_per_thread * team_->size())) : 0;
    Writer top(*this, team_ ? &*team_ : nullptr, handoff, true);
    // A range of m references has at most m - 1 interior nodes (a split leaves references on
    // both sides), so with room for that many the array is never copied as it grows.
    if (!team_) top.fragment().nodes.reserve(std::max(n - 1, 1));
    bvh.bounds = top.range_bounds(0, n);
    if (n > 0) {
      const std::optional<Split> split = top.choose_split(0, n, bvh.bounds, 0);
      if (split) {
        top.emit_interior(*split, 0, n, 0);
      } else {
        // The whole mesh fits one leaf. The traversal starts at a node, so the root is a node
        // whose child 0 is that leaf and whose child 1 is empty (an empty box no ray enters).
        BvhNode root;
        root.box[0] = bvh.bounds;
        root.first[0] = 0;
        root.count[0] = n;
        root.first[1] = -1;
        root.count[1] = 0;
        top.fragment().nodes.push_back(root);
        top.fragment().stats.nodes = 1;
        top.count_leaf(n);
      }
    }
    top.report_progress();
    build_subtrees();
    bvh.stats = std::move(top.fragment().stats);
    bvh.stats.threads = team_ ? team_->size() : 1;
    for (const Subtree& s : subtrees_) add_stats(bvh.stats, s.fragment.stats);
    bvh.nodes = splice(top.fragment().nodes);
    bvh.triangle_ids.resize(n);
    for (int i = 0; i < n; ++i) bvh.triangle_ids[i] = references_[i].id;
  }

private:
  // Builds a subtree, or the top of the tree, depth first into its own Fragment. With a team,
  // its passes over large nodes are shared and its children of at most `handoff` triangles
  // become Subtrees; without one it is the serial build.
  class Writer {
  public:
    Writer(Builder& builder, ThreadTeam* team, int handoff, bool reports_progress)
        : b_(builder), options_(builder.options_), refs_(builder.references_.data()),
          team_(team), handoff_(handoff), reports_progress_(reports_progress),
          bins_(3 * static_cast<std::size_t>(options_.bins)), right_area_(options_.bins),
          right_count_(options_.bins), used_(options_.bins) {
      out_.stats.leaf_sizes.assign(options_.max_leaf_size + 1, 0);
      if (team_) thread_bins_.resize(team_->size());
    }

    Fragment& fragment() { return out_; }

    // Builds the Subtree's nodes into its own fragment (with room for all of them, as the
    // serial build's: see Builder::build).
    void build(Subtree& subtree) {
      out_.nodes.reserve(subtree.end - subtree.begin - 1);
      emit_interior(subtree.split, subtree.begin, subtree.end, subtree.depth);
      report_progress();
      subtree.fragment = std::move(out_);
      out_ = Fragment{};
      out_.stats.leaf_sizes.assign(options_.max_leaf_size + 1, 0);
    }

    void count_leaf(int count) {
      ++out_.stats.leaves;
      ++out_.stats.leaf_sizes[count];
      unreported_ += count;
      if (unreported_ >= k_progress_step) report_progress();
    }

    // Adds the triangles placed since the last report to the build's count. Not done for every
    // leaf: with leaves of one that is a clock read per triangle, and the threads would take
    // turns owning the counter's cache line.
    void report_progress() {
      const long long placed = b_.placed_ += unreported_;
      unreported_ = 0;
      // CpuProgress prints from the thread that made it: the calling thread, member 0.
      if (reports_progress_) b_.progress_.update(placed);
    }

    Aabb range_bounds(int begin, int end) {
      return reduce_boxes(begin, end, [](const Reference& r) { return r.box; });
    }

    Aabb centroid_bounds(int begin, int end) {
      return reduce_boxes(begin, end, [](const Reference& r) {
        Aabb box;
        box.grow(r.centroid);
        return box;
      });
    }

    // Writes the interior node for `split` and, depth first, everything below it; returns the
    // node's index. Child 0's subtree is written before child 1 is even decided, so an
    // interior child 0 is always the next node, and the leaves come out in the order of the
    // reference array.
    int emit_interior(const Split& split, int begin, int end, int depth) {
      std::vector<BvhNode>& nodes = out_.nodes;
      const int index = static_cast<int>(nodes.size());
      nodes.emplace_back();
      ++out_.stats.nodes;
      out_.stats.depth = std::max(out_.stats.depth, depth);
      const int child_begin[2] = {begin, split.mid};
      const int child_end[2] = {split.mid, end};
      const Aabb child_box[2] = {split.left, split.right};
      for (int c = 0; c < 2; ++c) {
        const std::optional<Split> child_split =
            choose_split(child_begin[c], child_end[c], child_box[c], depth + 1);
        int first = child_begin[c];
        int count = child_end[c] - child_begin[c];
        if (child_split && count <= handoff_) {
          // Left for a thread of the second phase; its number is stored until the splice.
          first = -1 - static_cast<int>(b_.subtrees_.size());
          Subtree& subtree = b_.subtrees_.emplace_back();
          subtree.split = *child_split;
          subtree.begin = child_begin[c];
          subtree.end = child_end[c];
          subtree.depth = depth + 1;
          subtree.position = static_cast<int>(nodes.size());
          count = 0;
        } else if (child_split) {
          first = emit_interior(*child_split, child_begin[c], child_end[c], depth + 1);
          count = 0;
        } else {
          count_leaf(count);
        }
        // Written through the index: the recursion above may have moved the array.
        nodes[index].box[c] = child_box[c];
        nodes[index].first[c] = first;
        nodes[index].count[c] = count;
      }
      return index;
    }

    // How the references [begin, end) are split, or nothing when they become a leaf.
    std::optional<Split> choose_split(int begin, int end, const Aabb& box, int depth) {
      const int n = end - begin;
      const int max_leaf = options_.max_leaf_size;
      if (options_.method == SplitMethod::median) {
        if (n <= max_leaf) return std::nullopt;
        return median_split(begin, end);
      }
      if (n == 1) return std::nullopt; // a leaf of one: there is nothing to split
      const SahPlane best =
          n == 2 ? pair_plane(begin, box, depth) : best_sah_plane(begin, end, box, depth);
      const auto apply = [&] {
        return n == 2 ? split_pair(best, begin) : apply_sah_plane(best, begin, end);
      };
      if (n <= max_leaf) {
        // A leaf costs n triangle tests; split only if the SAH expects fewer.
        if (best.axis >= 0 && best.cost < n) return apply();
        return std::nullopt;
      }
      if (best.axis >= 0) return apply();
      // Too many triangles for a leaf and no plane separates their centroids (they all
      // coincide) or keeps under the depth bound: halve the range, which always does both.
      return median_split(begin, end);
    }

  private:
    // Whether the team shares the passes over [begin, end).
    bool shared(int begin, int end) const {
      return team_ != nullptr && end - begin >= k_min_shared_pass;
    }

    // The union of box_of(r) over the references [begin, end): each member joins its slice,
    // then the slices are joined. Min and max round nothing, so the box is the serial one.
    template <class BoxOf> Aabb reduce_boxes(int begin, int end, BoxOf box_of) {
      const auto join_slice = [&](int from, int to) {
        Aabb box;
        for (int i = from; i < to; ++i) box.grow(box_of(refs_[i]));
        return box;
      };
      if (!shared(begin, end)) return join_slice(begin, end);
      std::vector<Aabb> slices(team_->size());
      team_->run([&](int t) {
        const auto [from, to] = team_->slice(begin, end, t);
        slices[t] = join_slice(from, to);
      });
      Aabb box;
      for (const Aabb& s : slices) box.grow(s);
      return box;
    }

    // [listing:median_split]
    // The object median: along the longest axis of the centroids' bounds, the half of the
    // triangles with the smaller centroids goes left. std::nth_element finds that half in time
    // linear in n, without sorting. The children hold floor(n/2) and ceil(n/2) triangles, so
    // the tree is balanced whatever the geometry; its boxes may overlap badly, which the SAH
    // avoids. When every centroid is the same, any half will do: the range is halved as it is.
    Split median_split(int begin, int end) {
      const Aabb centroids = centroid_bounds(begin, end);
      const Vec3d extent =
          centroids.hi.as<double>() - centroids.lo.as<double>(); // may pass 3e38
      const int axis =
          extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
      const int mid = begin + (end - begin) / 2;
      if (extent[axis] > 0.0) {
        std::nth_element(refs_ + begin, refs_ + mid, refs_ + end,
                         [&](const Reference& a, const Reference& b) {
                           return a.centroid[axis] < b.centroid[axis];
                         });
      }
      return {mid, range_bounds(begin, mid), range_bounds(mid, end)};
    }
    // [/listing:median_split]

    // Bin k along an axis holds the centroids c with floor((c - origin) * scale) == k. The
    // arithmetic is double: the centroids' extent can exceed the largest float, and the same
    // rounding, applied in the same order, sorts triangles into bins and later into children.
    // Both are monotone in c, so no triangle lands on the wrong side of the chosen plane.
    int bin_of(float c, int axis) const {
      const int k = static_cast<int>((static_cast<double>(c) - origin_[axis]) * scale_[axis]);
      return std::min(k, options_.bins - 1);
    }

    // [listing:sah_split]
    // Drops the references [begin, end) into `bins` (bins per axis, axis after axis).
    void fill_bins(int begin, int end, Bin* bins) const {
      const int bin_count = options_.bins;
      for (int i = begin; i < end; ++i) {
        const Reference& r = refs_[i];
        for (int axis = 0; axis < 3; ++axis) {
          if (scale_[axis] == 0.0) continue; // every centroid on one plane: nothing to separate
          Bin& bin = bins[axis * bin_count + bin_of(r.centroid[axis], axis)];
          grow_bin(bin, r);
          ++bin.count;
        }
      }
    }

    // The bins of [begin, end): with a team, each member bins its slice into bins of its own,
    // and the bins are merged bin by bin.
    void bin_references(int begin, int end) {
      std::fill(bins_.begin(), bins_.end(), Bin{});
      if (!shared(begin, end)) return fill_bins(begin, end, bins_.data());
      team_->run([&](int t) {
        thread_bins_[t].assign(bins_.size(), Bin{});
        const auto [from, to] = team_->slice(begin, end, t);
        fill_bins(from, to, thread_bins_[t].data());
      });
      for (const std::vector<Bin>& bins : thread_bins_) {
        for (std::size_t k = 0; k < bins_.size(); ++k) {
          bins_[k].grow(bins[k].box());
          bins_[k].count += bins[k].count;
        }
      }
    }

    SahPlane best_sah_plane(int begin, int end, const Aabb& box, int depth) {
      const int bin_count = options_.bins;
      const Aabb centroids = centroid_bounds(begin, end);
      for (int axis = 0; axis < 3; ++axis) {
        const double extent =
            static_cast<double>(centroids.hi[axis]) - static_cast<double>(centroids.lo[axis]);
        origin_[axis] = centroids.lo[axis];
        scale_[axis] = extent > 0.0 ? bin_count / extent : 0.0; // 0: no plane on this axis
      }
      // Binned SAH (Wald 2007). Drop every triangle into one of `bins` equal slices of the
      // centroids' bounds, on each axis, keeping each bin's count and box. The planes between
      // bins are the candidate splits; each is priced, in units of one triangle test, as one
      // node visit plus each side's triangles weighted by the chance that a ray through this
      // node enters that side's box:
      //   cost = 1 + A(left) / A(node) * n(left) + A(right) / A(node) * n(right).
      // A sweep from the right records every plane's right side, one from the left prices the
      // planes as it goes: the binning is linear in n, the sweeps in the number of bins.
      bin_references(begin, end);
      const double node_area = half_area_of(box);
      SahPlane best;
      for (int axis = 0; axis < 3; ++axis) {
        if (scale_[axis] == 0.0) continue;
        const Bin* bin = &bins_[axis * bin_count];
        // Planes with an empty bin beside them repeat a neighbour's split: the distinct splits
        // lie between consecutive non-empty bins, so list those first (without a branch).
        int used_count = 0;
        for (int k = 0; k < bin_count; ++k) {
          used_[used_count] = k;
          used_count += bin[k].count > 0;
        }
        Aabb right;
        int right_count = 0;
        for (int u = used_count - 1; u > 0; --u) {
          right.grow(bin[used_[u]].box());
          right_count += bin[used_[u]].count;
          right_area_[u] = half_area_of(right);
          right_count_[u] = right_count;
        }
        Aabb left;
        int left_count = 0;
        for (int u = 1; u < used_count; ++u) { // the plane just left of bin used_[u]
          left.grow(bin[used_[u - 1]].box());
          left_count += bin[used_[u - 1]].count;
          const double cost = 1.0 + area_ratio(half_area_of(left), node_area) * left_count +
                              area_ratio(right_area_[u], node_area) * right_count_[u];
          if (cost < best.cost &&
              within_depth_bound(depth, left_count, right_count_[u], options_.max_leaf_size)) {
            best = {axis, used_[u], cost};
          }
        }
      }
      // [/listing:sah_split]
      return best;
    }

    // Partitions the range in place at the chosen plane. The children's boxes are the unions
    // of their bins' boxes, which are exactly the bounds of their triangles (min and max round
    // nothing).
    Split apply_sah_plane(const SahPlane& best, int begin, int end) {
      const int axis = best.axis;
      const auto goes_left = [&](const Reference& r) {
        return bin_of(r.centroid[axis], axis) < best.plane;
      };
      Split split;
      split.mid = shared(begin, end) ? partition_shared(begin, end, goes_left)
                                     : partition_references(refs_, begin, end, goes_left);
      // A loop per side: growing a box chosen bin by bin would keep both boxes in memory, each
      // grow waiting for the last one's stores.
      const Bin* bin = &bins_[axis * options_.bins];
      for (int k = 0; k < best.plane; ++k) split.left.grow(bin[k].box());
      for (int k = best.plane; k < options_.bins; ++k) split.right.grow(bin[k].box());
      return split;
    }

    // Two references: the node that a tree with leaves of one holds most often (43% of the
    // conference room's interior nodes). The binned search needs no bins for them. On an axis
    // where their centroids differ, the lower centroid falls in the first bin and the other in
    // a later one, so the one plane there sends a triangle to each side; where they are equal
    // there is no plane. What is left to choose is the axis, priced exactly as best_sah_plane
    // prices a plane (with counts of one), and the same axis wins.
    SahPlane pair_plane(int begin, const Aabb& box, int depth) const {
      const Reference& a = refs_[begin];
      const Reference& b = refs_[begin + 1];
      const double node_area = half_area_of(box);
      SahPlane best;
      for (int axis = 0; axis < 3; ++axis) {
        if (a.centroid[axis] == b.centroid[axis]) continue;
        const bool a_left = a.centroid[axis] < b.centroid[axis];
        const double cost = 1.0 + area_ratio(half_area_of((a_left ? a : b).box), node_area) +
                            area_ratio(half_area_of((a_left ? b : a).box), node_area);
        if (cost < best.cost && within_depth_bound(depth, 1, 1, options_.max_leaf_size))
          best = {axis, 1, cost};
      }
      return best;
    }

    // The pair split along best.axis as apply_sah_plane splits it: Hoare's partition swaps
    // the two only when the second one belongs on the left, and each child's box, the union
    // of one triangle's bin with empty ones, is that triangle's box.
    Split split_pair(const SahPlane& best, int begin) {
      Reference* pair = refs_ + begin;
      if (pair[1].centroid[best.axis] < pair[0].centroid[best.axis])
        std::swap(pair[0], pair[1]);
      return {begin + 1, pair[0].box, pair[1].box};
    }

    // partition_references' outcome, computed by the team: each member marks its slice and
    // counts the references that must move (those going right in the left part, those going
    // left in the right part); with the counts of the slices before it, each member knows the
    // rank of every one of its movers, lists them by rank, and the k-th of the left part
    // trades places with the k-th of the right part.
    template <class GoesLeft> int partition_shared(int begin, int end, GoesLeft goes_left) {
      const int members = team_->size();
      goes_left_.resize(static_cast<std::size_t>(end - begin));
      std::vector<int> left_of(members), movers_left(members), movers_right(members);
      team_->run([&](int t) {
        const auto [from, to] = team_->slice(begin, end, t);
        unsigned char* flags = goes_left_.data();
        int count = 0;
        for (int i = from; i < to; ++i) {
          const bool left = goes_left(refs_[i]);
          flags[i - begin] = left;
          count += left;
        }
        left_of[t] = count;
      });
      int mid = begin;
      for (const int count : left_of) mid += count;
      const auto moves = [&](int i) { return goes_left_[i - begin] != (i < mid); };
      team_->run([&](int t) {
        const auto [left_from, left_to] = team_->slice(begin, mid, t);
        const auto [right_from, right_to] = team_->slice(mid, end, t);
        int count = 0;
        for (int i = left_from; i < left_to; ++i) count += moves(i);
        movers_left[t] = count;
        count = 0;
        for (int i = right_from; i < right_to; ++i) count += moves(i);
        movers_right[t] = count;
      });
      // Ranks: the left part's movers counted from the left, the right part's from the right.
      std::vector<int> rank_left(members), rank_right(members);
      int movers = 0;
      for (int t = 0; t < members; ++t) {
        rank_left[t] = movers;
        movers += movers_left[t];
      }
      int from_right = 0;
      for (int t = members - 1; t >= 0; --t) {
        rank_right[t] = from_right;
        from_right += movers_right[t];
      }
      mover_left_.resize(movers);
      mover_right_.resize(movers);
      team_->run([&](int t) {
        const auto [left_from, left_to] = team_->slice(begin, mid, t);
        const auto [right_from, right_to] = team_->slice(mid, end, t);
        int k = rank_left[t];
        for (int i = left_from; i < left_to; ++i)
          if (moves(i)) mover_left_[k++] = i;
        k = rank_right[t];
        for (int i = right_to - 1; i >= right_from; --i)
          if (moves(i)) mover_right_[k++] = i;
      });
      team_->run([&](int t) {
        const auto [from, to] = team_->slice(0, movers, t);
        for (int k = from; k < to; ++k)
          std::swap(refs_[mover_left_[k]], refs_[mover_right_[k]]);
      });
      return mid;
    }

    Builder& b_;
    const BuildOptions& options_;
    Reference* refs_; // the builder's references; this writer touches only its ranges
    ThreadTeam* team_;
    int handoff_;
    bool reports_progress_;
    int unreported_ = 0; // triangles placed in leaves since the last report_progress
    Fragment out_;
    // Scratch of the SAH search, reused by every node.
    std::vector<Bin> bins_; // bins per axis, axis after axis
    std::vector<double> right_area_;
    std::vector<int> right_count_;
    std::vector<int> used_; // the non-empty bins of one axis
    double origin_[3] = {};
    double scale_[3] = {};
    // Scratch of the shared passes.
    std::vector<std::vector<Bin>> thread_bins_;
    std::vector<unsigned char> goes_left_;
    std::vector<int> mover_left_, mover_right_;
  };

  // The second phase: the team's members take the subtrees, largest first, each building one
  // alone at a time. Which thread builds which changes nothing in what is built.
  void build_subtrees() {
    if (subtrees_.empty()) return;
    std::vector<int> order(subtrees_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return subtrees_[a].end - subtrees_[a].begin > subtrees_[b].end - subtrees_[b].begin;
    });
    std::atomic<std::size_t> next{0};
    team_->run([&](int t) {
      Writer writer(*this, nullptr, 0, t == 0);
      for (std::size_t i = next++; i < order.size(); i = next++)
        writer.build(subtrees_[order[i]]);
    });
  }

  static void add_stats(BuildStats& total, const BuildStats& part) {
    total.nodes += part.nodes;
    total.leaves += part.leaves;
    total.depth = std::max(total.depth, part.depth);
    for (std::size_t k = 0; k < part.leaf_sizes.size(); ++k)
      total.leaf_sizes[k] += part.leaf_sizes[k];
  }

  // The whole node array in the serial depth-first order: the top's nodes, with each subtree's
  // nodes inserted where the top had `position` nodes, all node numbers shifted to match.
  std::vector<BvhNode> splice(std::vector<BvhNode>& top) {
    if (subtrees_.empty()) return std::move(top);
    const int top_count = static_cast<int>(top.size());
    std::vector<int> index_of(top_count); // each top node's index in the whole tree
    std::size_t s = 0;
    int shift = 0; // nodes of the subtrees placed so far
    for (int j = 0; j <= top_count; ++j) {
      for (; s < subtrees_.size() && subtrees_[s].position <= j; ++s) {
        subtrees_[s].start = j + shift;
        shift += static_cast<int>(subtrees_[s].fragment.nodes.size());
      }
      if (j < top_count) index_of[j] = j + shift;
    }
    std::vector<BvhNode> nodes(static_cast<std::size_t>(top_count + shift));
    for (int j = 0; j < top_count; ++j) {
      BvhNode node = top[j];
      for (int c = 0; c < 2; ++c) {
        if (node.is_leaf(c)) continue;
        const int first = node.first[c];
        node.first[c] = first >= 0 ? index_of[first] : subtrees_[-1 - first].start;
      }
      nodes[index_of[j]] = node;
    }
    std::atomic<std::size_t> next{0};
    team_->run([&](int) {
      for (std::size_t i = next++; i < subtrees_.size(); i = next++) {
        const Subtree& subtree = subtrees_[i];
        BvhNode* out = nodes.data() + subtree.start;
        for (BvhNode node : subtree.fragment.nodes) {
          for (int c = 0; c < 2; ++c)
            if (!node.is_leaf(c)) node.first[c] += subtree.start;
          *out++ = node;
        }
      }
    });
    return nodes;
  }

  const BuildOptions& options_;
  // Millions of triangles take seconds to build: the build says how far it has come.
  CpuProgress progress_;
  std::atomic<long long> placed_{0};  // triangles in leaves so far
  std::vector<Reference> references_; // one per triangle, partitioned in place into leaf order
  std::optional<ThreadTeam> team_;    // none with one thread, or for a small mesh
  std::vector<Subtree> subtrees_;     // handed out by the top phase, in the order it met them
};

} // namespace

void check_build_options(const BuildOptions& options) {
  if (options.max_leaf_size < 1 || options.max_leaf_size > k_max_leaf_size) {
    throw InputError("--leaf-size " + std::to_string(options.max_leaf_size) +
                     ": a leaf holds 1 to " + std::to_string(k_max_leaf_size) + " triangles");
  }
  if (options.bins < 2 || options.bins > k_max_bins) {
    throw InputError("--bins " + std::to_string(options.bins) + ": the SAH takes 2 to " +
                     std::to_string(k_max_bins) + " bins per axis");
  }
  if (options.method != SplitMethod::median && options.method != SplitMethod::sah &&
      options.method != SplitMethod::sbvh) {
    throw InputError("unknown split method " +
                     std::to_string(static_cast<int>(options.method)) +
                     " (the build knows median, sah and sbvh)");
  }
  // Written so that NaN fails too. Past 4 the references could pass the int range of 1 << 28
  // triangles, and no scene of the course gains from a fraction of that.
  if (!(options.split_budget >= 0.0 && options.split_budget <= k_max_split_budget)) {
    char line[160];
    std::snprintf(line, sizeof line,
                  "--split-budget %g: spatial splits may add 0 to %g times the triangles",
                  options.split_budget, k_max_split_budget);
    throw InputError(line);
  }
  if (options.threads < 0 || options.threads > k_max_build_threads) {
    throw InputError("build threads " + std::to_string(options.threads) +
                     ": 0 (the CPU backend's) to " + std::to_string(k_max_build_threads));
  }
}

void check_build_input(const ch04::Mesh& mesh) {
  const auto triangle_count = static_cast<long long>(mesh.triangles.size());
  if (triangle_count > k_max_bvh_triangles)
    throw InputError(std::to_string(triangle_count) + " triangles: a BVH holds at most " +
                     std::to_string(k_max_bvh_triangles));
  const auto vertex_count = static_cast<long long>(mesh.vertices.size());
  for (long long i = 0; i < triangle_count; ++i) {
    const ch04::IndexedTriangle& t = mesh.triangles[i];
    for (const int v : {t.v0, t.v1, t.v2}) {
      if (v < 0 || v >= vertex_count)
        throw InputError("triangle " + std::to_string(i) + ": vertex index " +
                         std::to_string(v) + " is out of range (the mesh has " +
                         std::to_string(vertex_count) + " vertices)");
      const Vec3f p = mesh.vertices[v];
      if (!(ch04::is_finite(p.x) && ch04::is_finite(p.y) && ch04::is_finite(p.z))) {
        char line[200];
        std::snprintf(line, sizeof line, "triangle %lld: vertex %d is not finite (%g, %g, %g)",
                      i, v, static_cast<double>(p.x), static_cast<double>(p.y),
                      static_cast<double>(p.z));
        throw InputError(line);
      }
    }
  }
}

Bvh build_bvh(const ch04::Mesh& mesh, const BuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check_build_options(options);
  check_build_input(mesh);
  const auto triangle_count = static_cast<long long>(mesh.triangles.size());
  Bvh bvh;
  bvh.options = options;
  const CpuWorkName work("building the tree");
  const int threads = options.threads > 0 ? options.threads : cpu_thread_count();
  if (options.method == SplitMethod::sbvh) {
    build_sbvh(mesh, options, bvh);
  } else {
    Builder(mesh, options, threads).build(bvh);
  }
  // The triangles copied into leaf order: a gather from all over the mesh, shared by the
  // threads. Each copy has its own place, so the array is the same for any count.
  bvh.triangles.resize(bvh.triangle_ids.size());
  for_each_index_cpu(
      bvh.triangles.size(),
      [&](std::size_t k) { bvh.triangles[k] = mesh.triangle(bvh.triangle_ids[k]); }, threads,
      "triangles");
  bvh.stats.sah_cost = sah_cost(bvh);
  if (triangle_count > 0) {
    const double bytes =
        static_cast<double>(bvh.nodes.size() * sizeof(BvhNode)) +
        static_cast<double>(bvh.triangle_ids.size()) * (sizeof(TriangleF) + sizeof(int));
    bvh.stats.bytes_per_triangle = bytes / static_cast<double>(triangle_count);
  }
  bvh.stats.triangles = triangle_count;
  bvh.stats.references = static_cast<long long>(bvh.triangle_ids.size());
  bvh.stats.build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
          .count();
  return bvh;
}

double sah_cost(const Bvh& bvh) {
  const double root_area = half_area_of(bvh.bounds);
  double cost = 0.0;
  for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
    const BvhNode& node = bvh.nodes[i];
    const Aabb own = i == 0 ? bvh.bounds : join(node.box[0], node.box[1]);
    cost += area_ratio(half_area_of(own), root_area);
    for (int c = 0; c < 2; ++c) {
      if (node.is_leaf(c)) {
        cost += area_ratio(half_area_of(node.box[c]), root_area) * node.count[c];
      }
    }
  }
  return cost;
}

} // namespace rt::ch07
