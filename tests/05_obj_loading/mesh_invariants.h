// Chapter 05 tests: what every loaded mesh must satisfy, whichever file it came from. The
// tests check it on the good files; the fuzzer (fuzz_obj.cpp) checks it on every input that
// loads, so a mesh that is quietly wrong counts as a bug just as a crash does.
#pragma once

#include <string>
#include <vector>

#include "obj_loader.h"

namespace rt::testing {

namespace detail {

inline bool finite(float x) { return x - x == 0.0f; } // false for infinities and NaN

inline bool in_range(const ch04::IndexedTriangle& t, std::size_t count, bool may_be_absent) {
  const auto ok = [&](int i) {
    return (i >= 0 && static_cast<std::size_t>(i) < count) || (may_be_absent && i == -1);
  };
  return ok(t.v0) && ok(t.v1) && ok(t.v2);
}

} // namespace detail

// Empty when the mesh is consistent, otherwise what is wrong with it.
inline std::string mesh_invariant_violation(const ch05::ObjMesh& mesh) {
  using detail::finite;
  using detail::in_range;
  const std::vector<ch04::IndexedTriangle>& triangles = mesh.geometry.triangles;
  const std::size_t n = triangles.size();
  if (n == 0) return "a mesh without triangles";
  if (mesh.material_ids.size() != n) return "not one material id per triangle";
  if (mesh.normal_indices.size() != (mesh.normals.empty() ? 0 : n)) return "normal indices";
  if (mesh.texcoord_indices.size() != (mesh.texcoords.empty() ? 0 : n)) return "uv indices";
  if (mesh.object_count < 1) return "object count below 1";
  if (mesh.degenerate_triangle_count < 0 ||
      static_cast<std::size_t>(mesh.degenerate_triangle_count) > n) {
    return "degenerate triangle count";
  }
  for (const Vec3f& p : mesh.geometry.vertices) {
    if (!finite(p.x) || !finite(p.y) || !finite(p.z)) return "a non-finite position";
  }
  for (const Vec3f& p : mesh.normals) {
    if (!finite(p.x) || !finite(p.y) || !finite(p.z)) return "a non-finite normal";
  }
  for (const Vec2f& p : mesh.texcoords) {
    if (!finite(p.x) || !finite(p.y)) return "a non-finite texture coordinate";
  }
  Vec3f low = mesh.geometry.vertices.empty() ? Vec3f{} : mesh.geometry.vertices[0];
  Vec3f high = low;
  for (std::size_t i = 0; i < n; ++i) {
    if (!in_range(triangles[i], mesh.geometry.vertices.size(), false)) return "vertex index";
    if (!mesh.normals.empty() && !in_range(mesh.normal_indices[i], mesh.normals.size(), true)) {
      return "normal index";
    }
    if (!mesh.texcoords.empty() &&
        !in_range(mesh.texcoord_indices[i], mesh.texcoords.size(), true)) {
      return "texture coordinate index";
    }
    const int material = mesh.material_ids[i];
    if (material < -1 || material >= static_cast<int>(mesh.material_names.size())) {
      return "material id";
    }
    const ch04::TriangleF t = mesh.geometry.triangle(static_cast<int>(i));
    if (i == 0) low = high = t.v0;
    for (const Vec3f& p : {t.v0, t.v1, t.v2}) {
      low = elementwise_min(low, p);
      high = elementwise_max(high, p);
    }
  }
  if (low != mesh.bounds_min || high != mesh.bounds_max) return "bounds";
  return {};
}

} // namespace rt::testing
