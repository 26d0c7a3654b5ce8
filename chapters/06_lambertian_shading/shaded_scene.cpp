// Chapter 06: scenes to shade. See shaded_scene.h.
#include "shaded_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>

#include "rt/error.h"
#include "supported_range.h"

namespace rt::ch06 {
namespace {

constexpr Palette k_palette{{{0.75f, 0.75f, 0.72f}, // slot 0: the floor, unassigned faces
                             {0.85f, 0.30f, 0.25f}, // the sphere
                             {0.25f, 0.45f, 0.85f}, // the box
                             {0.55f, 0.75f, 0.35f},
                             {0.90f, 0.70f, 0.30f},
                             {0.60f, 0.45f, 0.75f},
                             {0.35f, 0.70f, 0.70f},
                             {0.85f, 0.55f, 0.60f}}};

// 1e+06 rather than 1000000.000000.
std::string short_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

bool finite(Vec3d v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Appends a mesh part to the scene in palette slot `slot`, with `normals` and per-triangle
// `normal_indices` into them.
void append(ShadedScene& scene, const ch04::Mesh& part, std::uint8_t slot,
            const std::vector<Vec3f>& normals,
            const std::vector<IndexedTriangle>& normal_indices) {
  const int vertex_base = static_cast<int>(scene.mesh.vertices.size());
  const int normal_base = static_cast<int>(scene.normals.size());
  scene.mesh.vertices.insert(scene.mesh.vertices.end(), part.vertices.begin(),
                             part.vertices.end());
  scene.normals.insert(scene.normals.end(), normals.begin(), normals.end());
  for (std::size_t i = 0; i < part.triangles.size(); ++i) {
    const IndexedTriangle t = part.triangles[i], n = normal_indices[i];
    scene.mesh.triangles.push_back(
        {t.v0 + vertex_base, t.v1 + vertex_base, t.v2 + vertex_base});
    scene.normal_indices.push_back(
        {n.v0 + normal_base, n.v1 + normal_base, n.v2 + normal_base});
    scene.material.push_back(slot);
  }
}

// Smooth: the computed normal of each vertex, indexed like the positions.
void append_smooth(ShadedScene& scene, const ch04::Mesh& part, std::uint8_t slot) {
  append(scene, part, slot, compute_vertex_normals(part), part.triangles);
}

// Faceted: every corner of a triangle gets the triangle's own normal, shared by the triangles
// of one plane, so smooth shading leaves the edges between planes sharp.
void append_faceted(ShadedScene& scene, const ch04::Mesh& part, std::uint8_t slot) {
  std::vector<Vec3f> normals;
  std::vector<IndexedTriangle> normal_indices;
  std::map<std::array<float, 3>, int> index_of;
  for (int i = 0; i < static_cast<int>(part.triangles.size()); ++i) {
    const ch04::TriangleF t = part.triangle(i);
    const Vec3d face =
        cross(t.v1.as<double>() - t.v0.as<double>(), t.v2.as<double>() - t.v0.as<double>());
    const double face_length = length(face);
    // A triangle with no area gets (0, 0, 0): shading falls back to its geometric normal.
    const Vec3f n = face_length > 0.0 ? (face / face_length).as<float>() : Vec3f{};
    const auto [found, added] =
        index_of.emplace(std::array<float, 3>{n.x, n.y, n.z}, static_cast<int>(normals.size()));
    if (added) normals.push_back(n);
    normal_indices.push_back({found->second, found->second, found->second});
  }
  append(scene, part, slot, normals, normal_indices);
}

ch04::Mesh scaled(ch04::Mesh mesh, double scale) {
  for (Vec3f& v : mesh.vertices) v = (v.as<double>() * scale).as<float>();
  return mesh;
}

} // namespace

unsigned features_used(const ShadedScene& scene, bool smooth, bool shadows) {
  const bool any_light = scene.lights.directional_count + scene.lights.point_count > 0;
  return (smooth ? k_smooth_normals : 0u) | (shadows && any_light ? k_shadows : 0u) |
         (scene.lights.point_count > 0 ? k_point_lights : 0u);
}

Bounds bounds_of(const ch04::Mesh& mesh) {
  if (mesh.triangles.empty()) throw InputError("the scene has no triangles to render");
  Vec3f lo = mesh.vertices[mesh.triangles[0].v0], hi = lo;
  for (const IndexedTriangle& t : mesh.triangles) {
    for (const int v : {t.v0, t.v1, t.v2}) {
      lo = elementwise_min(lo, mesh.vertices[v]);
      hi = elementwise_max(hi, mesh.vertices[v]);
    }
  }
  return {lo.as<double>(), hi.as<double>()};
}

CameraSpec frame_bounds_down_z(const Bounds& bounds, double fov_degrees, Extent extent) {
  const double half_vertical = fov_degrees * std::numbers::pi / 360.0;
  const double half_horizontal =
      std::atan(std::tan(half_vertical) * double(extent.width) / extent.height);
  const double half_fov = std::min(half_vertical, half_horizontal);
  // Triangles that all lie at one point have no size: any distance will do.
  const double radius = bounds.radius() > 0.0 ? bounds.radius() : 1.0;
  CameraSpec camera;
  camera.target = bounds.centre();
  camera.eye = bounds.centre() + Vec3d{0.0, 0.0, 1.0} * (radius / std::sin(half_fov));
  camera.fov_degrees = fov_degrees;
  // Near the edge of the supported range the eye, further out than the box, lies beyond it;
  // a tiny box far from the origin can round onto its centre in float.
  const double farthest = max_component(elementwise_abs(camera.eye));
  if (!(farthest <= ch03::k_max_coordinate) ||
      camera.eye.as<float>() == camera.target.as<float>()) {
    std::ostringstream what;
    what.precision(3);
    what << "cannot frame the model: its bounding box (radius " << radius
         << ") needs a camera ";
    if (!(farthest <= ch03::k_max_coordinate))
      what << farthest << " from the origin, beyond the supported +-" << ch03::k_max_coordinate;
    else
      what << "that float rounds onto its target";
    what << "; give --eye and --target";
    throw InputError(what.str());
  }
  return camera;
}

void validate_lights(const LightSettings& settings) {
  if (!finite(settings.direction) || !(length(settings.direction) > 0.0))
    throw UsageError("--light-dir must be a finite, non-zero direction");
  if (!(settings.ambient >= 0.0 && settings.ambient <= 1.0))
    throw UsageError("--ambient must lie between 0 and 1");
}

Lights make_lights(const Bounds& bounds, const LightSettings& settings) {
  Lights lights;
  lights.ambient = Vec3f{1.0f, 1.0f, 1.0f} * float(settings.ambient);
  lights.directional_count = 1;
  lights.directional[0] = {normalize(settings.direction).as<float>(), {0.75f, 0.75f, 0.7f}};
  if (settings.point_light) {
    const Vec3d position = bounds.centre() + Vec3d{0.9, 1.4, 0.8} * bounds.radius();
    const double distance_squared = length_squared(position - bounds.centre());
    lights.point_count = 1;
    lights.point[0] = {position.as<float>(),
                       (Vec3d{0.55, 0.45, 0.33} * distance_squared).as<float>()};
  }
  return lights;
}

ShadedScene make_default_scene(int sphere_subdivisions, double scale,
                               const LightSettings& lights) {
  ShadedScene scene;
  scene.palette = k_palette;
  append_smooth(scene,
                scaled(ch04::make_icosphere(sphere_subdivisions, {-1.2, 1.0, 0.0}, 1.0), scale),
                1);
  append_faceted(scene, scaled(ch04::make_box({0.6, 0.0, -0.8}, {2.2, 1.6, 0.8}, 2), scale), 2);
  ch04::Mesh floor; // a quad: two triangles sharing a diagonal
  for (const Vec3d corner :
       {Vec3d{-6, 0, -6}, Vec3d{6, 0, -6}, Vec3d{6, 0, 6}, Vec3d{-6, 0, 6}})
    floor.vertices.push_back((corner * scale).as<float>());
  floor.triangles = {{0, 2, 1}, {0, 3, 2}};
  // The lights are placed for the sphere and the box; the floor is only the ground.
  scene.lights = make_lights(bounds_of(scene.mesh), lights);
  append_faceted(scene, floor, 0);
  scene.description = std::to_string(scene.mesh.triangles.size()) +
                      " triangles: icosphere (computed vertex normals, angle-weighted), box "
                      "and floor quad (a normal per face)";
  if (scale != 1.0) scene.description += ", scaled by " + short_number(scale);
  ch04::check_supported_range(scene.mesh,
                              "the built-in scene scaled by " + short_number(scale));
  return scene;
}

CameraSpec default_camera(double scale) {
  CameraSpec camera{{0.0, 2.2, 6.5}, {0.3, 0.7, 0.0}, {0.0, 1.0, 0.0}, 40.0};
  camera.eye = camera.eye * scale;
  camera.target = camera.target * scale;
  return camera;
}

ShadedScene make_lone_sphere(int subdivisions, double scale, const LightSettings& lights) {
  ShadedScene scene;
  scene.palette = k_palette;
  append_smooth(scene, ch04::make_icosphere(subdivisions, Vec3d{2.0, 1.0, -3.0} * scale, scale),
                1);
  scene.lights = make_lights(bounds_of(scene.mesh), lights);
  scene.description = "icosphere of " + std::to_string(scene.mesh.triangles.size()) +
                      " triangles, radius " + short_number(scale);
  ch04::check_supported_range(scene.mesh, "a sphere of radius " + short_number(scale));
  return scene;
}

ShadedScene scene_from_obj(const ch05::ObjMesh& obj, const LightSettings& lights,
                           NormalWeighting weighting) {
  ShadedScene scene;
  scene.mesh = obj.geometry;
  scene.palette = k_palette;
  const std::size_t triangles = obj.geometry.triangles.size();
  if (obj.material_ids.size() != triangles)
    throw InputError("scene_from_obj: a material id per triangle expected");
  scene.material.reserve(triangles);
  for (const int id : obj.material_ids)
    scene.material.push_back(static_cast<std::uint8_t>(id < 0 ? 0 : 1 + id % 7));
  scene.lights = make_lights(bounds_of(scene.mesh), lights);
  scene.description = std::to_string(triangles) + " triangles, ";
  if (obj.normals.empty()) { // one computed normal per position: the triangles index them
    scene.normals = compute_vertex_normals(scene.mesh, weighting);
    scene.description += std::string("vertex normals computed (") + to_string(weighting) + ")";
    return scene;
  }
  if (obj.normal_indices.size() != triangles)
    throw InputError("scene_from_obj: normal indices for every triangle expected");
  scene.normals = obj.normals;
  scene.normal_indices = obj.normal_indices;
  // Corners the file gave no normal (-1) take the computed normal of their position.
  long long missing = 0;
  const int computed_base = static_cast<int>(scene.normals.size());
  for (std::size_t i = 0; i < triangles; ++i) {
    const IndexedTriangle& t = scene.mesh.triangles[i];
    IndexedTriangle& n = scene.normal_indices[i];
    for (auto [normal, position] : {std::pair{&n.v0, t.v0}, {&n.v1, t.v1}, {&n.v2, t.v2}}) {
      if (*normal >= 0) continue;
      *normal = computed_base + position;
      ++missing;
    }
  }
  if (missing > 0) {
    const std::vector<Vec3f> computed = compute_vertex_normals(scene.mesh, weighting);
    scene.normals.insert(scene.normals.end(), computed.begin(), computed.end());
  }
  scene.description += "vertex normals from the file";
  if (missing > 0)
    scene.description += " (" + std::to_string(missing) + " corners without: computed, " +
                         to_string(weighting) + ")";
  return scene;
}

std::size_t scene_bytes(const ShadedScene& scene, unsigned features) {
  std::size_t bytes = scene.mesh.vertices.size() * sizeof(Vec3f) +
                      scene.mesh.triangles.size() * sizeof(IndexedTriangle) +
                      scene.material.size() * sizeof(std::uint8_t);
  if (features & k_smooth_normals)
    bytes += scene.normals.size() * sizeof(Vec3f) +
             scene.normal_indices.size() * sizeof(IndexedTriangle);
  return bytes;
}

SceneView host_view(const ShadedScene& scene, unsigned features) {
  SceneView view{ch04::host_view(scene.mesh),
                 scene.material.data(),
                 nullptr,
                 nullptr,
                 scene.palette,
                 scene.lights,
                 scene.lift_shadow_origins};
  if (features & k_smooth_normals) {
    view.normals = scene.normals.data();
    view.normal_indices = scene.normal_indices.empty() ? scene.mesh.triangles.data()
                                                       : scene.normal_indices.data();
  }
  return view;
}

ShadedScene load_framed_obj(const std::string& path, CameraSpec& camera, Extent extent,
                            bool eye_given, bool target_given) {
  ShadedScene scene = scene_from_obj(ch05::load_obj(path), LightSettings{});
  const CameraSpec framed =
      frame_bounds_down_z(bounds_of(scene.mesh), camera.fov_degrees, extent);
  if (!eye_given) camera.eye = framed.eye;
  if (!target_given) camera.target = framed.target;
  return scene;
}

} // namespace rt::ch06
