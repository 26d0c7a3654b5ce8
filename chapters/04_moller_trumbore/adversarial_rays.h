// Chapter 04: the rays most likely to slip through a closed mesh. Fired from inside, aimed
// exactly at its vertices and at points on its edges (every edge of a closed mesh is shared),
// they must each hit at least one triangle; one that hits nothing has leaked.
#pragma once

#include <random>
#include <vector>

#include "mesh_gen.h"

namespace rt::ch04 {

using ch03::RayF;

// A ray of the leak test and what it was aimed at (for the picture of where rays leak).
struct AimedRay {
  RayF ray;
  Vec3f target;   // the vertex or the point of an edge
  bool at_vertex; // else at an edge
};

// `count` rays from random points within `spread` of `inside` (that whole ball must lie inside
// the mesh): a third aimed at vertices, the rest at random points of random edges. Targets
// and directions are rounded to float like any ray's, so each ray passes within an ulp or so
// of its vertex or edge: exactly where the two variants round differently.
inline std::vector<AimedRay> aimed_rays(const Mesh& mesh, Vec3f inside, float spread, int count,
                                        unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), along(0.0f, 1.0f);
  std::uniform_int_distribution<int> pick_vertex(0, int(mesh.vertices.size()) - 1);
  std::uniform_int_distribution<int> pick_triangle(0, int(mesh.triangles.size()) - 1);
  std::uniform_int_distribution<int> pick_edge(0, 2), pick_kind(0, 2);
  std::vector<AimedRay> rays;
  rays.reserve(count);
  while (static_cast<int>(rays.size()) < count) {
    const Vec3f jitter{unit(rng), unit(rng), unit(rng)};
    if (!(length_squared(jitter) <= 1.0f)) continue; // uniform in the ball
    const Vec3f origin = inside + jitter * spread;
    Vec3f target;
    const bool at_vertex = pick_kind(rng) == 0;
    if (at_vertex) {
      target = mesh.vertices[pick_vertex(rng)];
    } else {
      const IndexedTriangle& t = mesh.triangles[pick_triangle(rng)];
      const int edge = pick_edge(rng);
      const Vec3f a = mesh.vertices[edge == 0 ? t.v0 : edge == 1 ? t.v1 : t.v2];
      const Vec3f b = mesh.vertices[edge == 0 ? t.v1 : edge == 1 ? t.v2 : t.v0];
      target = a + (b - a) * along(rng);
    }
    rays.push_back({RayF{origin, target - origin}, target, at_vertex});
  }
  return rays;
}

// The same rays without their targets.
inline std::vector<RayF> rays_at_vertices_and_edges(const Mesh& mesh, Vec3f inside,
                                                    float spread, int count, unsigned seed) {
  std::vector<RayF> rays;
  rays.reserve(count);
  for (const AimedRay& aimed : aimed_rays(mesh, inside, spread, count, seed))
    rays.push_back(aimed.ray);
  return rays;
}

} // namespace rt::ch04
