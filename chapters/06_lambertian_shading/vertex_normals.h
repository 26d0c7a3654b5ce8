// Chapter 06: vertex normals for meshes whose file gives none. Each vertex gets the blend of
// the unit normals of the triangles around it. Weighted by the angle each triangle makes at
// the vertex (Thürmer & Wüthrich 1998), the result depends on the surface only, not on how it
// was cut into triangles; weighted by area (the plain cross product, the common shortcut) it
// leans towards whichever side happens to have more or larger triangles.
#pragma once

#include <vector>

#include "mesh_gen.h"
#include "rt/vec.h"

namespace rt::ch06 {

enum class NormalWeighting { angle, area };

const char* to_string(NormalWeighting weighting);

// One unit normal per entry of mesh.vertices, computed in double and rounded once. Triangles
// with no area add nothing; a vertex no triangle gives a direction (unused, only slivers
// around it, or normals that cancel exactly) gets (0, 0, 0), which shading treats as "use the
// face's normal".
std::vector<Vec3f> compute_vertex_normals(const ch04::Mesh& mesh,
                                          NormalWeighting weighting = NormalWeighting::angle);

} // namespace rt::ch06
