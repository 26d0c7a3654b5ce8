// Chapter 06: vertex normals from faces. See vertex_normals.h.
#include "vertex_normals.h"

#include <cmath>

namespace rt::ch06 {
namespace {

// The angle between two vectors, accurate for every angle (acos of a dot product loses
// everything near 0 and pi).
double angle_between(Vec3d a, Vec3d b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

} // namespace

const char* to_string(NormalWeighting weighting) {
  return weighting == NormalWeighting::angle ? "angle-weighted" : "area-weighted";
}

// [listing:vertex_normals]
std::vector<Vec3f> compute_vertex_normals(const ch04::Mesh& mesh, NormalWeighting weighting) {
  std::vector<Vec3d> sum(mesh.vertices.size());
  for (const ch04::IndexedTriangle& t : mesh.triangles) {
    const int corner[3] = {t.v0, t.v1, t.v2};
    Vec3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = mesh.vertices[corner[k]].as<double>();
    const Vec3d face = cross(p[1] - p[0], p[2] - p[0]); // length: twice the area
    const double face_length = length(face);
    if (!(face_length > 0.0 && std::isfinite(face_length))) continue; // no direction
    for (int k = 0; k < 3; ++k) {
      const Vec3d to_next = p[(k + 1) % 3] - p[k], to_previous = p[(k + 2) % 3] - p[k];
      sum[corner[k]] += weighting == NormalWeighting::area
                            ? face
                            : face * (angle_between(to_next, to_previous) / face_length);
    }
  }
  std::vector<Vec3f> normals(sum.size());
  for (std::size_t i = 0; i < sum.size(); ++i) {
    const double sum_length = length(sum[i]);
    if (sum_length > 0.0) normals[i] = (sum[i] / sum_length).as<float>();
  }
  return normals;
}
// [/listing:vertex_normals]

} // namespace rt::ch06
