// Chapter 04: closed triangle meshes made by code, for tests that fire rays from inside.
// Vertices are shared through indices, so two triangles meeting at an edge use the very same
// floats for its end points: the precondition of every watertightness argument.
#pragma once

#include <string>
#include <vector>

#include "rt/vec.h"
#include "triangle.h"

namespace rt::ch04 {

struct IndexedTriangle {
  int v0, v1, v2; // indices into Mesh::vertices, counter-clockwise seen from outside
};

struct Mesh {
  std::vector<Vec3f> vertices;            // each position stored once
  std::vector<IndexedTriangle> triangles; // neighbours name the same vertex indices

  TriangleF triangle(int i) const {
    const IndexedTriangle& t = triangles[i];
    return {vertices[t.v0], vertices[t.v1], vertices[t.v2]};
  }
};

// A sphere made from an icosahedron whose faces are split in four `subdivisions` times
// (20 * 4^subdivisions triangles), vertices computed in double and rounded once to float.
Mesh make_icosphere(int subdivisions, Vec3d centre, double radius);

// An axis-aligned box whose faces are grids of `cells` x `cells` squares, two triangles each.
Mesh make_box(Vec3d min_corner, Vec3d max_corner, int cells);

// Several meshes in one: `from`'s vertices appended to `to`'s, and its triangles with their
// indices moved past `to`'s old vertices.
void append_mesh(Mesh& to, const Mesh& from);

// The longest side of the box around a triangle (computed in double, exact for float corners).
double triangle_span(const TriangleF& triangle);

// Zero area in float: repeated or collinear corners, or corners so close together that the
// cross product of the edges underflows to zero. Neither intersection test ever hits one.
bool is_flat(const TriangleF& triangle);

// Throws InputError "<what>: <problem>" unless the mesh lies in the range the float pipeline
// supports (chapter 03's supported_range.h): every vertex within +-k_max_coordinate, every
// triangle flat or spanning at least k_min_length, and at least one triangle not flat.
void check_supported_range(const Mesh& mesh, const std::string& what);

// Directed edges that have no partner running the other way: 0 for a closed, consistently
// oriented mesh in which every edge is shared by exactly two triangles.
int count_unpaired_edges(const Mesh& mesh);

} // namespace rt::ch04
