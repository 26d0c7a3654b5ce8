// Chapter 04: closed meshes made by code. See mesh_gen.h.
#include "mesh_gen.h"

#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <utility>

#include "rt/error.h"
#include "supported_range.h"

namespace rt::ch04 {

namespace {

// Geometry is built in double on the unit sphere and rounded to float once, at the end, so
// a vertex has one float position however many triangles use it.
Mesh round_to_float(const std::vector<Vec3d>& positions,
                    std::vector<IndexedTriangle> triangles) {
  Mesh mesh;
  mesh.vertices.reserve(positions.size());
  for (const Vec3d& p : positions) mesh.vertices.push_back(p.as<float>());
  mesh.triangles = std::move(triangles);
  return mesh;
}

} // namespace

Mesh make_icosphere(int subdivisions, Vec3d centre, double radius) {
  if (subdivisions < 0 || subdivisions > 8) throw InputError("icosphere: subdivisions 0..8");
  const double phi = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3d> unit = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
                             {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
                             {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  for (Vec3d& p : unit) p = normalize(p);
  std::vector<IndexedTriangle> triangles = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint_of; // one new vertex per edge, shared
    const auto midpoint = [&](int a, int b) {
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      const auto found = midpoint_of.find(key);
      if (found != midpoint_of.end()) return found->second;
      unit.push_back(normalize(unit[a] + unit[b]));
      const int index = static_cast<int>(unit.size()) - 1;
      midpoint_of.emplace(key, index);
      return index;
    };
    std::vector<IndexedTriangle> finer;
    finer.reserve(triangles.size() * 4);
    for (const IndexedTriangle& t : triangles) {
      const int ab = midpoint(t.v0, t.v1), bc = midpoint(t.v1, t.v2), ca = midpoint(t.v2, t.v0);
      finer.insert(finer.end(), {{t.v0, ab, ca}, {t.v1, bc, ab}, {t.v2, ca, bc}, {ab, bc, ca}});
    }
    triangles = std::move(finer);
  }
  for (Vec3d& p : unit) p = centre + p * radius;
  return round_to_float(unit, std::move(triangles));
}

Mesh make_box(Vec3d min_corner, Vec3d max_corner, int cells) {
  if (cells < 1 || cells > 1024) throw InputError("box: cells per edge 1..1024");
  // Lattice points (i, j, k), 0..cells on each axis; only those on the surface get a vertex.
  const int side = cells + 1;
  std::vector<int> vertex_of(static_cast<std::size_t>(side) * side * side, -1);
  std::vector<Vec3d> positions;
  const auto vertex = [&](std::array<int, 3> lattice) {
    int& index = vertex_of[(static_cast<std::size_t>(lattice[2]) * side + lattice[1]) * side +
                           lattice[0]];
    if (index < 0) {
      const Vec3d fraction{double(lattice[0]) / cells, double(lattice[1]) / cells,
                           double(lattice[2]) / cells};
      positions.push_back(min_corner + (max_corner - min_corner) * fraction);
      index = static_cast<int>(positions.size()) - 1;
    }
    return index;
  };
  std::vector<IndexedTriangle> triangles;
  for (int axis = 0; axis < 3; ++axis) {
    const int axis_u = (axis + 1) % 3, axis_v = (axis + 2) % 3; // u x v points along +axis
    for (const int level : {0, cells}) {
      const bool outward_is_positive = level == cells;
      for (int cell_u = 0; cell_u < cells; ++cell_u) {
        for (int cell_v = 0; cell_v < cells; ++cell_v) {
          const auto corner = [&](int du, int dv) {
            std::array<int, 3> lattice{};
            lattice[axis] = level;
            lattice[axis_u] = cell_u + du;
            lattice[axis_v] = cell_v + dv;
            return vertex(lattice);
          };
          const int c00 = corner(0, 0), c10 = corner(1, 0), c11 = corner(1, 1),
                    c01 = corner(0, 1);
          if (outward_is_positive) {
            triangles.insert(triangles.end(), {{c00, c10, c11}, {c00, c11, c01}});
          } else {
            triangles.insert(triangles.end(), {{c00, c11, c10}, {c00, c01, c11}});
          }
        }
      }
    }
  }
  return round_to_float(positions, std::move(triangles));
}

double triangle_span(const TriangleF& triangle) {
  const Vec3d a = triangle.v0.as<double>(), b = triangle.v1.as<double>(),
              c = triangle.v2.as<double>();
  const Vec3d extent =
      elementwise_max(a, elementwise_max(b, c)) - elementwise_min(a, elementwise_min(b, c));
  return max_component(extent);
}

bool is_flat(const TriangleF& triangle) {
  return cross(triangle.v1 - triangle.v0, triangle.v2 - triangle.v0) == Vec3f{};
}

void check_supported_range(const Mesh& mesh, const std::string& what) {
  const auto fail = [&](const std::string& problem) {
    std::ostringstream text;
    text.precision(3);
    text << what << ": " << problem;
    throw InputError(text.str());
  };
  long long flat = 0;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const TriangleF t = mesh.triangle(static_cast<int>(i));
    for (const Vec3f& p : {t.v0, t.v1, t.v2}) {
      const double farthest = max_component(elementwise_abs(p.as<double>()));
      if (!(farthest <= ch03::k_max_coordinate)) {
        std::ostringstream problem;
        problem.precision(3);
        problem << "triangle " << i << " has a vertex at " << farthest
                << " from the origin, beyond the supported +-" << ch03::k_max_coordinate;
        fail(problem.str());
      }
    }
    if (is_flat(t)) {
      ++flat;
    } else if (triangle_span(t) < ch03::k_min_length) {
      std::ostringstream problem;
      problem.precision(3);
      problem << "triangle " << i << " spans only " << triangle_span(t)
              << "; a triangle that is not flat must span at least " << ch03::k_min_length;
      fail(problem.str());
    }
  }
  if (flat == static_cast<long long>(mesh.triangles.size()))
    fail(mesh.triangles.empty() ? std::string("no triangles")
                                : "all " + std::to_string(flat) +
                                      " triangles are flat (zero area in float): nothing "
                                      "to intersect");
}

int count_unpaired_edges(const Mesh& mesh) {
  std::map<std::pair<int, int>, int> directed_edges;
  for (const IndexedTriangle& t : mesh.triangles) {
    ++directed_edges[{t.v0, t.v1}];
    ++directed_edges[{t.v1, t.v2}];
    ++directed_edges[{t.v2, t.v0}];
  }
  int unpaired = 0;
  for (const auto& [edge, count] : directed_edges) {
    const auto reverse = directed_edges.find({edge.second, edge.first});
    const bool paired = count == 1 && reverse != directed_edges.end() && reverse->second == 1;
    unpaired += paired ? 0 : count;
  }
  return unpaired;
}

void append_mesh(Mesh& to, const Mesh& from) {
  const int base = static_cast<int>(to.vertices.size());
  to.vertices.insert(to.vertices.end(), from.vertices.begin(), from.vertices.end());
  for (const IndexedTriangle& t : from.triangles)
    to.triangles.push_back({t.v0 + base, t.v1 + base, t.v2 + base});
}

} // namespace rt::ch04
