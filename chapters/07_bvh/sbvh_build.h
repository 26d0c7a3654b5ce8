// Chapter 07: spatial splits (Stich, Friedrich and Dietrich, "Spatial Splits in Bounding Volume
// Hierarchies", HPG 2009). A long thin triangle lying across a scene makes every box that holds
// it long: the object splits of the SAH cannot separate it from its neighbours, and the boxes
// of siblings overlap. A spatial split cuts the node's box by a plane instead and gives each
// child the part of every triangle on its side, so a triangle may be referenced by several
// leaves. build_bvh calls build_sbvh for SplitMethod::sbvh; the clipping is exposed for its
// tests.
#pragma once

#include "bvh.h"
#include "mesh_gen.h"

namespace rt::ch07 {

// The box of the part of `triangle` that lies in the slab lo <= p[axis] <= hi (lo may be -inf,
// hi +inf), or the empty box when no part of it does. Computed in double and rounded outward to
// float, so that it contains every point of the triangle in the slab: a box rounded to nearest
// could miss a sliver of the triangle, and a ray through that sliver would leak (see the .cpp).
Aabb clipped_bounds(const TriangleF& triangle, int axis, float lo, float hi);

// The box both boxes share; the empty box when they do not meet.
Aabb intersection_of(const Aabb& a, const Aabb& b);

// The SBVH build: at each node the best binned object split, and, where its children's boxes
// overlap by more than 1e-5 of the root's area, the best spatial split of the node's box,
// whichever the SAH prices lower. The references may grow to (1 + split_budget) times the
// triangles. Called by build_bvh once the options and the mesh are checked; it fills nodes,
// triangle_ids (the references in leaf order, a triangle once per leaf that holds it), bounds
// and the stats of the tree's shape.
void build_sbvh(const ch04::Mesh& mesh, const BuildOptions& options, Bvh& bvh);

} // namespace rt::ch07
