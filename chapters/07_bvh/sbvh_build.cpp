// Chapter 07: the SBVH build, spatial splits beside the binned SAH's object splits. See
// sbvh_build.h.
#include "sbvh_build.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "bvh_build.h"
#include "rt/cpu_progress.h"

namespace rt::ch07 {

namespace {

constexpr float k_inf = std::numeric_limits<float>::infinity();

// The largest float not above d, and the smallest not below it: a double rounded outward.
float float_below(double d) {
  float f = static_cast<float>(d);
  if (static_cast<double>(f) > d) f = std::nextafter(f, -k_inf);
  return f;
}
float float_above(double d) {
  float f = static_cast<float>(d);
  if (static_cast<double>(f) < d) f = std::nextafter(f, k_inf);
  return f;
}

// [listing:sbvh_clip]
// Grows `box` by the point where the edge a -> b crosses the plane p[axis] = plane (the edge
// crosses it strictly: a and b lie on either side). The point is a + (b - a) * s with
// s = (plane - a[axis]) / (b[axis] - a[axis]). On the plane's own axis it is `plane`, a float,
// exactly. On the other axes double arithmetic makes six roundings of at most 2^-53 each, on
// numbers no larger than |a| + |b|, so the computed coordinate is within 2^-49 (|a| + |b|) of
// the true one; the box takes a margin eight times that, never leaves the edge's own range, and
// is rounded outward to float. Rounding to nearest instead, or clipping in float, can put the
// box's face a hair inside the triangle: the sliver outside belongs to no leaf's box, and a ray
// through it passes between the two halves of the triangle. That is a leak, the very thing
// chapter 04's watertight test was written to prevent.
void grow_by_crossing(Aabb& box, Vec3f a, Vec3f b, int axis, float plane) {
  const double s = (static_cast<double>(plane) - a[axis]) /
                   (static_cast<double>(b[axis]) - static_cast<double>(a[axis]));
  float lo[3], hi[3];
  for (int c = 0; c < 3; ++c) {
    if (c == axis) {
      lo[c] = hi[c] = plane;
      continue;
    }
    const double ac = a[c], bc = b[c];
    const double x = ac + (bc - ac) * s;
    const double margin = (std::abs(ac) + std::abs(bc)) * 0x1p-46;
    lo[c] = float_below(std::max(x - margin, std::min(ac, bc)));
    hi[c] = float_above(std::min(x + margin, std::max(ac, bc)));
  }
  box.grow(Vec3f{lo[0], lo[1], lo[2]});
  box.grow(Vec3f{hi[0], hi[1], hi[2]});
}
// [/listing:sbvh_clip]

// The box of the points where the triangle's edges cross the plane p[axis] = plane (empty when
// none crosses it strictly; an infinite plane is crossed by none).
Aabb crossing_bounds(const TriangleF& triangle, int axis, float plane) {
  const Vec3f v[3] = {triangle.v0, triangle.v1, triangle.v2};
  Aabb box;
  for (int i = 0; i < 3; ++i) {
    const Vec3f a = v[i], b = v[(i + 1) % 3];
    if ((a[axis] < plane && plane < b[axis]) || (b[axis] < plane && plane < a[axis]))
      grow_by_crossing(box, a, b, axis, plane);
  }
  return box;
}

// The box of the triangle's corners in the slab lo <= p[axis] <= hi.
Aabb corner_bounds(const TriangleF& triangle, int axis, float lo, float hi) {
  Aabb box;
  for (const Vec3f& v : {triangle.v0, triangle.v1, triangle.v2})
    if (v[axis] >= lo && v[axis] <= hi) box.grow(v);
  return box;
}

} // namespace

// The part of a triangle in a slab is a convex polygon whose corners are the triangle's
// corners inside the slab and the points where its edges cross the slab's two planes. Each of
// those is computed from the triangle's own vertices, never from an earlier clip, so the errors
// do not pile up.
Aabb clipped_bounds(const TriangleF& triangle, int axis, float lo, float hi) {
  Aabb box = corner_bounds(triangle, axis, lo, hi);
  box.grow(crossing_bounds(triangle, axis, lo));
  box.grow(crossing_bounds(triangle, axis, hi));
  return box;
}

Aabb intersection_of(const Aabb& a, const Aabb& b) {
  Aabb both;
  both.lo = elementwise_max(a.lo, b.lo);
  both.hi = elementwise_min(a.hi, b.hi);
  return both.empty() ? Aabb{} : both;
}

namespace {

// A reference: one triangle, or the part of it inside the region of the node that holds it.
// The box contains every point of the triangle inside that region (by the clip above), and
// is at most the triangle's own box.
struct Reference {
  Aabb box;
  int id; // the mesh's number of the triangle
};

Vec3f centroid_of(const Aabb& box) { return 0.5f * box.lo + 0.5f * box.hi; }

double area_ratio(double child_area, double parent_area) {
  return parent_area > 0.0 ? child_area / parent_area : 1.0;
}

// bvh_build.cpp's depth test, for the same proof: a split is accepted only when its larger
// child keeps d + halving_levels(n) <= k_max_bvh_depth - 1. A spatial split may copy
// references into both children, so it is also accepted only when each child holds strictly
// fewer references than the node: the count shrinks along every path, and the median split,
// which halves, remains the fallback that always keeps the invariant.
bool within_depth_bound(int depth, long long left_count, long long right_count, int max_leaf) {
  const long long larger = std::max(left_count, right_count);
  return depth + 1 + halving_levels(larger, max_leaf) <= k_max_bvh_depth - 1;
}

struct Children {
  std::vector<Reference> left, right;
  Aabb left_box, right_box;
};

struct Candidate {
  int axis = -1; // -1: none
  int plane = 0; // object: the first bin on the right; spatial: the index of the plane
  double cost = std::numeric_limits<double>::infinity();
  Aabb left_box, right_box; // object splits: the children's boxes, for the overlap test
  float position = 0.0f;    // spatial splits: where the plane lies
};

Aabb bounds_of_references(const std::vector<Reference>& refs) {
  Aabb box;
  for (const Reference& r : refs) box.grow(r.box);
  return box;
}

class SbvhBuilder {
public:
  SbvhBuilder(const ch04::Mesh& mesh, const BuildOptions& options)
      : options_(options),
        progress_(static_cast<long long>(mesh.triangles.size()), "triangles in leaves") {
    const int n = static_cast<int>(mesh.triangles.size());
    triangles_.reserve(n);
    for (int i = 0; i < n; ++i) triangles_.push_back(mesh.triangle(i));
    reference_limit_ =
        n + static_cast<long long>(std::floor(options.split_budget * static_cast<double>(n)));
    references_ = n;
  }

  void build(Bvh& bvh) {
    const int n = static_cast<int>(triangles_.size());
    stats_.leaf_sizes.assign(options_.max_leaf_size + 1, 0);
    std::vector<Reference> refs(n);
    for (int i = 0; i < n; ++i) refs[i] = {bounds_of(triangles_[i]), i};
    bvh.bounds = bounds_of_references(refs);
    root_area_ = half_area_of(bvh.bounds);
    if (n > 0) {
      std::optional<Children> split = choose_split(refs, bvh.bounds, 0);
      if (split) {
        emit_interior(*split, 0);
      } else { // the whole mesh fits one leaf, as in bvh_build.cpp
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
        for (const Reference& r : refs) ids_.push_back(r.id);
      }
    }
    bvh.nodes = std::move(nodes_);
    bvh.triangle_ids = std::move(ids_);
    bvh.stats = std::move(stats_);
  }

private:
  int emit_interior(Children& split, int depth) {
    const int index = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    ++stats_.nodes;
    stats_.depth = std::max(stats_.depth, depth);
    std::vector<Reference>* child_refs[2] = {&split.left, &split.right};
    const Aabb child_box[2] = {split.left_box, split.right_box};
    for (int c = 0; c < 2; ++c) {
      std::vector<Reference> refs = std::move(*child_refs[c]);
      std::optional<Children> child_split = choose_split(refs, child_box[c], depth + 1);
      int first = static_cast<int>(ids_.size());
      const int count = child_split ? 0 : static_cast<int>(refs.size());
      if (child_split) {
        refs = {}; // free the memory before going deeper
        first = emit_interior(*child_split, depth + 1);
      } else {
        for (const Reference& r : refs) ids_.push_back(r.id);
        ++stats_.leaves;
        ++stats_.leaf_sizes[count];
        placed_ += count;
        progress_.update(
            std::min<long long>(placed_, static_cast<long long>(triangles_.size())));
      }
      nodes_[index].box[c] = child_box[c];
      nodes_[index].first[c] = first;
      nodes_[index].count[c] = count;
    }
    return index;
  }

  // How the references are split, or nothing when they become a leaf: as bvh_build.cpp's SAH
  // decides, with the spatial split as one more candidate.
  std::optional<Children> choose_split(std::vector<Reference>& refs, const Aabb& box,
                                       int depth) {
    const long long n = static_cast<long long>(refs.size());
    if (n == 1) return std::nullopt;
    const Candidate object = best_object_split(refs, box, depth);
    Candidate spatial;
    // The paper's test: spatial splits are tried only where the object split's children
    // overlap by a noticeable share of the root's area (alpha = 1e-5), which keeps the build
    // fast where object splits already separate the triangles, and the budget not spent.
    const bool overlap_large =
        object.axis < 0 || half_area_of(intersection_of(object.left_box, object.right_box)) >
                               k_spatial_alpha * root_area_;
    if (overlap_large && references_ < reference_limit_)
      spatial = best_spatial_split(refs, box, depth);
    const double leaf_cost = static_cast<double>(n);
    const bool must_split = n > options_.max_leaf_size;
    if (spatial.axis >= 0 && spatial.cost < object.cost &&
        (must_split || spatial.cost < leaf_cost)) {
      std::optional<Children> children = apply_spatial_split(refs, spatial, depth);
      if (children) return children;
    }
    if (object.axis >= 0 && (must_split || object.cost < leaf_cost))
      return apply_object_split(refs, object);
    if (!must_split) return std::nullopt;
    return median_split(refs);
  }

  int bin_of(float c, int axis) const {
    const int k = static_cast<int>((static_cast<double>(c) - origin_[axis]) * scale_[axis]);
    return std::min(k, options_.bins - 1);
  }

  // bvh_build.cpp's binned SAH over the references' centroids.
  Candidate best_object_split(const std::vector<Reference>& refs, const Aabb& box, int depth) {
    const int bins = options_.bins;
    Aabb centroids;
    for (const Reference& r : refs) centroids.grow(centroid_of(r.box));
    for (int axis = 0; axis < 3; ++axis) {
      const double extent =
          static_cast<double>(centroids.hi[axis]) - static_cast<double>(centroids.lo[axis]);
      origin_[axis] = centroids.lo[axis];
      scale_[axis] = extent > 0.0 ? bins / extent : 0.0;
    }
    bin_boxes_.assign(3 * static_cast<std::size_t>(bins), Aabb{});
    bin_counts_.assign(3 * static_cast<std::size_t>(bins), 0);
    for (const Reference& r : refs) {
      const Vec3f c = centroid_of(r.box);
      for (int axis = 0; axis < 3; ++axis) {
        if (scale_[axis] == 0.0) continue;
        const std::size_t k = axis * bins + bin_of(c[axis], axis);
        bin_boxes_[k].grow(r.box);
        ++bin_counts_[k];
      }
    }
    const double node_area = half_area_of(box);
    Candidate best;
    right_boxes_.resize(bins + 1);
    right_counts_.resize(bins + 1);
    for (int axis = 0; axis < 3; ++axis) {
      if (scale_[axis] == 0.0) continue;
      right_boxes_[bins] = Aabb{};
      right_counts_[bins] = 0;
      for (int k = bins - 1; k > 0; --k) {
        right_boxes_[k] = right_boxes_[k + 1];
        right_boxes_[k].grow(bin_boxes_[axis * bins + k]);
        right_counts_[k] = right_counts_[k + 1] + bin_counts_[axis * bins + k];
      }
      Aabb left;
      long long left_count = 0;
      for (int k = 1; k < bins; ++k) { // the plane between bins k - 1 and k
        left.grow(bin_boxes_[axis * bins + k - 1]);
        left_count += bin_counts_[axis * bins + k - 1];
        const long long right_count = right_counts_[k];
        if (left_count == 0 || right_count == 0) continue;
        const double cost = 1.0 + area_ratio(half_area_of(left), node_area) * left_count +
                            area_ratio(half_area_of(right_boxes_[k]), node_area) * right_count;
        if (cost < best.cost &&
            within_depth_bound(depth, left_count, right_count, options_.max_leaf_size)) {
          best.axis = axis;
          best.plane = k;
          best.cost = cost;
          best.left_box = left;
          best.right_box = right_boxes_[k];
        }
      }
    }
    if (best.axis >= 0) { // the scratch is reused by the next node: keep the origin and scale
      best_origin_ = origin_[best.axis];
      best_scale_ = scale_[best.axis];
    }
    return best;
  }

  Children apply_object_split(std::vector<Reference>& refs, const Candidate& best) {
    Children children;
    for (const Reference& r : refs) {
      const double c = centroid_of(r.box)[best.axis];
      int k = static_cast<int>((c - best_origin_) * best_scale_);
      k = std::min(k, options_.bins - 1);
      if (k < best.plane) {
        children.left.push_back(r);
        children.left_box.grow(r.box);
      } else {
        children.right.push_back(r);
        children.right_box.grow(r.box);
      }
    }
    return children;
  }

  // The spatial split's search. The node's box is cut into `bins` equal slabs along each axis;
  // the planes between them are the candidates. A reference goes left of plane P when its box
  // reaches below P (or lies flat on it), right when it reaches above P, and to both when it
  // straddles P. Each slab's box grows by the part of each reference's triangle inside that
  // slab: the triangle clipped to the slab, not the slab's cut of the reference's box, which
  // would be as loose as the box it came from. The cost is the SAH's, with the references
  // counted on each side: those that straddle the plane are paid for twice.
  Candidate best_spatial_split(const std::vector<Reference>& refs, const Aabb& box, int depth) {
    const int bins = options_.bins;
    const long long n = static_cast<long long>(refs.size());
    const double node_area = half_area_of(box);
    Candidate best;
    std::vector<float> planes(bins + 1);
    slab_boxes_.resize(bins);
    enter_.resize(bins + 1);
    leave_.resize(bins + 1);
    right_boxes_.resize(bins + 1);
    for (int axis = 0; axis < 3; ++axis) {
      const double lo = box.lo[axis], extent = static_cast<double>(box.hi[axis]) - lo;
      planes[0] = box.lo[axis];
      planes[bins] = box.hi[axis];
      for (int k = 1; k < bins; ++k) planes[k] = static_cast<float>(lo + extent * k / bins);
      bool increasing = true;
      for (int k = 1; k <= bins; ++k) increasing = increasing && planes[k] > planes[k - 1];
      if (!increasing) continue; // a box too thin for distinct planes along this axis
      std::fill(slab_boxes_.begin(), slab_boxes_.end(), Aabb{});
      std::fill(enter_.begin(), enter_.end(), 0);
      std::fill(leave_.begin(), leave_.end(), 0);
      const auto first_plane = planes.begin() + 1, last_plane = planes.begin() + bins;
      for (const Reference& r : refs) {
        const float rlo = r.box.lo[axis], rhi = r.box.hi[axis];
        // The first plane it is left of, and the first it is no longer right of.
        const int left_from = static_cast<int>(
            std::partition_point(first_plane, last_plane,
                                 [&](float p) { return !(rlo < p || rhi <= p); }) -
            planes.begin());
        const int right_until = static_cast<int>(
            std::partition_point(first_plane, last_plane, [&](float p) { return rhi > p; }) -
            planes.begin());
        ++enter_[left_from];
        ++leave_[right_until];
        // The slabs j, between planes j and j + 1, that its box touches.
        const int first_slab = std::max(
            0, static_cast<int>(std::lower_bound(planes.begin() + 1, planes.end(), rlo) -
                                planes.begin()) -
                   1);
        const int last_slab = std::min(
            bins - 1, static_cast<int>(std::upper_bound(planes.begin(), planes.end() - 1, rhi) -
                                       planes.begin()) -
                          1);
        if (first_slab >= last_slab) {
          slab_boxes_[std::max(0, first_slab)].grow(r.box);
          continue;
        }
        // clipped_bounds slab by slab, each plane's crossings computed once for the two slabs
        // that share it.
        const TriangleF& triangle = triangles_[r.id];
        Aabb below = crossing_bounds(triangle, axis, planes[first_slab]);
        for (int j = first_slab; j <= last_slab; ++j) {
          const Aabb above = crossing_bounds(triangle, axis, planes[j + 1]);
          Aabb part = corner_bounds(triangle, axis, planes[j], planes[j + 1]);
          part.grow(below);
          part.grow(above);
          slab_boxes_[j].grow(intersection_of(part, r.box));
          below = above;
        }
      }
      right_boxes_[bins] = Aabb{};
      for (int k = bins - 1; k >= 1; --k) {
        right_boxes_[k] = right_boxes_[k + 1];
        right_boxes_[k].grow(slab_boxes_[k]);
      }
      Aabb left;
      long long left_count = 0, right_count = n;
      for (int k = 1; k < bins; ++k) { // plane k, between slabs k - 1 and k
        left.grow(slab_boxes_[k - 1]);
        left_count += enter_[k];
        right_count -= leave_[k];
        if (left_count == 0 || right_count == 0 || left_count >= n || right_count >= n)
          continue; // a side that does not shrink could be split forever
        if (references_ + left_count + right_count - n > reference_limit_) continue;
        const double cost = 1.0 + area_ratio(half_area_of(left), node_area) * left_count +
                            area_ratio(half_area_of(right_boxes_[k]), node_area) * right_count;
        if (cost < best.cost &&
            within_depth_bound(depth, left_count, right_count, options_.max_leaf_size)) {
          best.axis = axis;
          best.plane = k;
          best.cost = cost;
          best.position = planes[k];
        }
      }
    }
    return best;
  }

  // Splits the references at the plane: a reference that straddles it is clipped into a part
  // on each side (a part whose clipped box turns out empty holds none of the triangle and is
  // dropped). The counts are those the search priced; they are checked again all the same, and
  // a split that would not shrink both sides, or would pass the budget, is not made.
  std::optional<Children> apply_spatial_split(const std::vector<Reference>& refs,
                                              const Candidate& best, int depth) {
    const int axis = best.axis;
    const float p = best.position;
    Children children;
    for (const Reference& r : refs) {
      const bool left = r.box.lo[axis] < p || r.box.hi[axis] <= p;
      const bool right = r.box.hi[axis] > p;
      if (left && right) {
        const TriangleF& triangle = triangles_[r.id];
        const Aabb below = intersection_of(clipped_bounds(triangle, axis, -k_inf, p), r.box);
        const Aabb above = intersection_of(clipped_bounds(triangle, axis, p, k_inf), r.box);
        if (!below.empty()) children.left.push_back({below, r.id});
        if (!above.empty()) children.right.push_back({above, r.id});
      } else if (left) {
        children.left.push_back(r);
      } else {
        children.right.push_back(r);
      }
    }
    const long long n = static_cast<long long>(refs.size());
    const long long nl = static_cast<long long>(children.left.size());
    const long long nr = static_cast<long long>(children.right.size());
    if (nl == 0 || nr == 0 || nl >= n || nr >= n ||
        references_ + nl + nr - n > reference_limit_ ||
        !within_depth_bound(depth, nl, nr, options_.max_leaf_size))
      return std::nullopt;
    references_ += nl + nr - n;
    ++stats_.spatial_splits;
    children.left_box = bounds_of_references(children.left);
    children.right_box = bounds_of_references(children.right);
    return children;
  }

  // bvh_build.cpp's fallback: half the references, by centroid along the longest axis.
  Children median_split(std::vector<Reference>& refs) {
    Aabb centroids;
    for (const Reference& r : refs) centroids.grow(centroid_of(r.box));
    const Vec3d extent = centroids.hi.as<double>() - centroids.lo.as<double>();
    const int axis =
        extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const auto mid = refs.begin() + static_cast<std::ptrdiff_t>(refs.size() / 2);
    if (extent[axis] > 0.0) {
      std::nth_element(refs.begin(), mid, refs.end(),
                       [&](const Reference& a, const Reference& b) {
                         return centroid_of(a.box)[axis] < centroid_of(b.box)[axis];
                       });
    }
    Children children;
    children.left.assign(refs.begin(), mid);
    children.right.assign(mid, refs.end());
    children.left_box = bounds_of_references(children.left);
    children.right_box = bounds_of_references(children.right);
    return children;
  }

  static constexpr double k_spatial_alpha = 1e-5;

  const BuildOptions& options_;
  CpuProgress progress_;
  long long placed_ = 0;
  std::vector<TriangleF> triangles_;
  long long references_ = 0;      // references in the tree being built, so far
  long long reference_limit_ = 0; // the triangles plus the budget
  double root_area_ = 0.0;
  std::vector<BvhNode> nodes_;
  std::vector<int> ids_; // the references' triangles, in leaf order
  BuildStats stats_;
  // Scratch reused by every node.
  std::vector<Aabb> bin_boxes_, slab_boxes_, right_boxes_;
  std::vector<long long> bin_counts_, right_counts_, enter_, leave_;
  double origin_[3] = {}, scale_[3] = {};
  double best_origin_ = 0.0, best_scale_ = 0.0;
};

} // namespace

void build_sbvh(const ch04::Mesh& mesh, const BuildOptions& options, Bvh& bvh) {
  SbvhBuilder(mesh, options).build(bvh);
}

} // namespace rt::ch07
