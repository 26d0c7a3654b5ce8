// Chapter 07: the BVH build, object median and binned SAH, and the checker that every test of
// the chapter runs on its trees. See bvh_build.h.
#include "bvh_build.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <string>

#include "rt/cpu_progress.h"
#include "rt/error.h"
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

struct Bin {
  Aabb box;      // bounds of the triangles whose centroid falls in this bin
  int count = 0; // how many there are
};

// The best SAH plane found: between bins plane - 1 and plane along `axis`.
struct SahPlane {
  int axis = -1; // -1: no plane splits this range
  int plane = 0;
  double cost = std::numeric_limits<double>::infinity();
};

class Builder {
public:
  Builder(const ch04::Mesh& mesh, const BuildOptions& options)
      : options_(options),
        progress_(static_cast<long long>(mesh.triangles.size()), "triangles in leaves"),
        bins_(3 * static_cast<std::size_t>(options.bins)), right_area_(options.bins),
        right_count_(options.bins), used_(options.bins) {
    const int n = static_cast<int>(mesh.triangles.size());
    references_.resize(n);
    for (int i = 0; i < n; ++i) { // check_build_input has vouched for every vertex
      Reference& r = references_[i];
      r.box = bounds_of(mesh.triangle(i));
      // Half of each end, not (v0 + v1 + v2) / 3 and not (lo + hi) / 2: both of those add
      // first, and the sum overflows to infinity for coordinates beyond half the largest float.
      r.centroid = 0.5f * r.box.lo + 0.5f * r.box.hi;
      r.id = i;
    }
  }

  // Builds the nodes, and leaves the references in leaf order.
  void build(Bvh& bvh) {
    const int n = static_cast<int>(references_.size());
    stats_.leaf_sizes.assign(options_.max_leaf_size + 1, 0);
    bvh.bounds = range_bounds(0, n);
    if (n > 0) {
      const std::optional<Split> split = choose_split(0, n, bvh.bounds, 0);
      if (split) {
        emit_interior(*split, 0, n, 0);
      } else {
        // The whole mesh fits one leaf. The traversal starts at a node, so the root is a node
        // whose child 0 is that leaf and whose child 1 is empty (an empty box no ray enters).
        BvhNode root;
        root.box[0] = bvh.bounds;
        root.first[0] = 0;
        root.count[0] = n;
        root.first[1] = -1;
        root.count[1] = 0;
        nodes_.push_back(root);
        stats_.nodes = 1;
        stats_.leaves = 1;
        ++stats_.leaf_sizes[n];
      }
    }
    bvh.nodes = std::move(nodes_);
    bvh.triangle_ids.reserve(n);
    for (const Reference& r : references_) bvh.triangle_ids.push_back(r.id);
    bvh.stats = std::move(stats_);
  }

private:
  Aabb range_bounds(int begin, int end) const {
    Aabb box;
    for (int i = begin; i < end; ++i) box.grow(references_[i].box);
    return box;
  }

  Aabb centroid_bounds(int begin, int end) const {
    Aabb box;
    for (int i = begin; i < end; ++i) box.grow(references_[i].centroid);
    return box;
  }

  // Writes the interior node for `split` and, depth first, everything below it; returns the
  // node's index. Child 0's subtree is written before child 1 is even decided, so an interior
  // child 0 is always the next node, and the leaves come out in the order of the reference
  // array.
  int emit_interior(const Split& split, int begin, int end, int depth) {
    const int index = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    ++stats_.nodes;
    stats_.depth = std::max(stats_.depth, depth);
    const int child_begin[2] = {begin, split.mid};
    const int child_end[2] = {split.mid, end};
    const Aabb child_box[2] = {split.left, split.right};
    for (int c = 0; c < 2; ++c) {
      const std::optional<Split> child_split =
          choose_split(child_begin[c], child_end[c], child_box[c], depth + 1);
      int first = child_begin[c];
      int count = child_end[c] - child_begin[c];
      if (child_split) {
        first = emit_interior(*child_split, child_begin[c], child_end[c], depth + 1);
        count = 0;
      } else {
        ++stats_.leaves;
        ++stats_.leaf_sizes[count];
        placed_ += count;
        progress_.update(placed_);
      }
      // Written through the index: the recursion above may have moved the array.
      nodes_[index].box[c] = child_box[c];
      nodes_[index].first[c] = first;
      nodes_[index].count[c] = count;
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
    const SahPlane best = best_sah_plane(begin, end, box, depth);
    if (n <= max_leaf) {
      // A leaf costs n triangle tests; split only if the SAH expects fewer.
      if (best.axis >= 0 && best.cost < n) return apply_sah_plane(best, begin, end);
      return std::nullopt;
    }
    if (best.axis >= 0) return apply_sah_plane(best, begin, end);
    // Too many triangles for a leaf and no plane separates their centroids (they all
    // coincide) or keeps under the depth bound: halve the range, which always does both.
    return median_split(begin, end);
  }

  // [listing:median_split]
  // The object median: along the longest axis of the centroids' bounds, the half of the
  // triangles with the smaller centroids goes left. std::nth_element finds that half in time
  // linear in n, without sorting. The children hold floor(n/2) and ceil(n/2) triangles, so
  // the tree is balanced whatever the geometry; its boxes may overlap badly, which the SAH
  // avoids. When every centroid is the same, any half will do: the range is halved as it is.
  Split median_split(int begin, int end) {
    const Aabb centroids = centroid_bounds(begin, end);
    const Vec3d extent = centroids.hi.as<double>() - centroids.lo.as<double>(); // may pass 3e38
    const int axis =
        extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const int mid = begin + (end - begin) / 2;
    if (extent[axis] > 0.0) {
      std::nth_element(references_.begin() + begin, references_.begin() + mid,
                       references_.begin() + end, [&](const Reference& a, const Reference& b) {
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

  SahPlane best_sah_plane(int begin, int end, const Aabb& box, int depth) {
    const int bin_count = options_.bins;
    const Aabb centroids = centroid_bounds(begin, end);
    for (int axis = 0; axis < 3; ++axis) {
      const double extent =
          static_cast<double>(centroids.hi[axis]) - static_cast<double>(centroids.lo[axis]);
      origin_[axis] = centroids.lo[axis];
      scale_[axis] = extent > 0.0 ? bin_count / extent : 0.0; // 0: no plane on this axis
      std::fill_n(bins_.begin() + axis * bin_count, bin_count, Bin{});
    }
    // [listing:sah_split]
    // Binned SAH (Wald 2007). Drop every triangle into one of `bins` equal slices of the
    // centroids' bounds, on each axis, keeping each bin's count and box. The planes between
    // bins are the candidate splits; each is priced, in units of one triangle test, as one node
    // visit plus each side's triangles weighted by the chance that a ray through this node
    // enters that side's box:
    //   cost = 1 + A(left) / A(node) * n(left) + A(right) / A(node) * n(right).
    // A sweep from the right records every plane's right side, one from the left prices the
    // planes as it goes: the binning is linear in n, the sweeps in the number of bins.
    for (int i = begin; i < end; ++i) {
      const Reference& r = references_[i];
      for (int axis = 0; axis < 3; ++axis) {
        if (scale_[axis] == 0.0) continue; // every centroid on one plane: nothing to separate
        Bin& bin = bins_[axis * bin_count + bin_of(r.centroid[axis], axis)];
        bin.box.grow(r.box);
        ++bin.count;
      }
    }
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
        right.grow(bin[used_[u]].box);
        right_count += bin[used_[u]].count;
        right_area_[u] = half_area_of(right);
        right_count_[u] = right_count;
      }
      Aabb left;
      int left_count = 0;
      for (int u = 1; u < used_count; ++u) { // the plane just left of bin used_[u]
        left.grow(bin[used_[u - 1]].box);
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

  // Partitions the range in place at the chosen plane. The children's boxes are the unions of
  // their bins' boxes, which are exactly the bounds of their triangles (min and max round
  // nothing).
  Split apply_sah_plane(const SahPlane& best, int begin, int end) {
    const int axis = best.axis;
    const auto middle = std::partition(
        references_.begin() + begin, references_.begin() + end,
        [&](const Reference& r) { return bin_of(r.centroid[axis], axis) < best.plane; });
    Split split;
    split.mid = static_cast<int>(middle - references_.begin());
    const Bin* bin = &bins_[axis * options_.bins];
    for (int k = 0; k < options_.bins; ++k) {
      (k < best.plane ? split.left : split.right).grow(bin[k].box);
    }
    return split;
  }

  const BuildOptions& options_;
  // Millions of triangles take seconds to build: the build says how far it has come.
  CpuProgress progress_;
  long long placed_ = 0;              // triangles in leaves so far
  std::vector<Reference> references_; // one per triangle, partitioned in place into leaf order
  std::vector<BvhNode> nodes_;
  BuildStats stats_;
  // Scratch of the SAH search, reused by every node.
  std::vector<Bin> bins_; // bins per axis, axis after axis
  std::vector<double> right_area_;
  std::vector<int> right_count_;
  std::vector<int> used_; // the non-empty bins of one axis
  double origin_[3] = {};
  double scale_[3] = {};
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
  if (options.method == SplitMethod::sbvh) {
    build_sbvh(mesh, options, bvh);
  } else {
    Builder(mesh, options).build(bvh);
  }
  bvh.triangles.reserve(bvh.triangle_ids.size());
  for (const int id : bvh.triangle_ids) bvh.triangles.push_back(mesh.triangle(id));
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
