// Chapter 11: scenes for light transport. See path_scene.h.
#include "path_scene.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include "animation.h"
#include "obj_loader.h"
#include "path_sampling.h"
#include "rt/error.h"
#include "rt/report.h"
#include "shaded_scene.h"

namespace rt::ch11 {
namespace {

constexpr PathMaterial k_default_material{{0.8f, 0.8f, 0.8f}, {0.0f, 0.0f, 0.0f}};

double triangle_area(const ch04::Mesh& mesh, int i) {
  const ch04::TriangleF t = mesh.triangle(i);
  const Vec3d a = t.v0.as<double>(), b = t.v1.as<double>(), c = t.v2.as<double>();
  return 0.5 * length(cross(b - a, c - a));
}

bool emits(const PathMaterial& m) {
  return m.emission.x != 0.0f || m.emission.y != 0.0f || m.emission.z != 0.0f;
}

void check_emission(const PathMaterial& m, const std::string& name) {
  const Vec3f e = m.emission;
  if (!std::isfinite(e.x) || !std::isfinite(e.y) || !std::isfinite(e.z))
    throw InputError("material '" + name + "': emission is not a finite number");
  if (e.x < 0.0f || e.y < 0.0f || e.z < 0.0f)
    throw InputError("material '" + name + "': negative emission (Ke) " +
                     std::to_string(std::min({e.x, e.y, e.z})));
}

std::string format_colour(Vec3d c) {
  std::ostringstream text;
  text << c.x << ' ' << c.y << ' ' << c.z;
  return text.str();
}

bool is_finite(Vec3d c) {
  return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
}

// An MTL material as this chapter's material: Kd and Ke checked first, since MTL files come
// from anywhere, and a value no surface or lamp can have would otherwise render as something
// else without a word. `lowered` is set when a Kd in (k_max_albedo, 1] was lowered.
PathMaterial path_material(const ch05::ObjMaterial& m, bool& lowered) {
  const std::string where = m.file + ": material '" + m.name + "': ";
  if (!m.unreadable.empty())
    throw InputError(where + m.unreadable + ": not three finite numbers");
  const Vec3d kd = m.diffuse, ke = m.emission; // tinyobjloader reads "0e999" as NaN
  if (!is_finite(kd) || !is_finite(ke))
    throw InputError(where + "Kd " + format_colour(kd) + ", Ke " + format_colour(ke) +
                     ": not finite numbers");
  if (!(min_component(kd) >= 0.0 && max_component(kd) <= 1.0))
    throw InputError(
        where + "Kd " + format_colour(kd) +
        ": an albedo lies in [0, 1] (a surface reflects at most what it receives)");
  if (!(min_component(ke) >= 0.0))
    throw InputError(where + "negative emission (Ke) " + format_colour(ke));
  if (!(max_component(ke) <= k_max_light))
    throw InputError(where + "Ke " + format_colour(ke) +
                     ": brighter than the brightest light this path tracer takes (" +
                     format_colour(Vec3d{k_max_light, k_max_light, k_max_light}) + ")");
  lowered = lowered || max_component(kd) > k_max_albedo;
  const auto albedo = [](double v) { return std::min(static_cast<float>(v), k_max_albedo); };
  return {{albedo(kd.x), albedo(kd.y), albedo(kd.z)},
          {static_cast<float>(ke.x), static_cast<float>(ke.y), static_cast<float>(ke.z)}};
}

// A unit-free regular polygon (disc) in the plane y = height, facing down.
ch04::Mesh make_disc(float radius, float height, int segments) {
  ch04::Mesh disc;
  disc.vertices.push_back({0.0f, height, 0.0f});
  for (int k = 0; k < segments; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / segments;
    disc.vertices.push_back({static_cast<float>(radius * std::cos(angle)), height,
                             static_cast<float>(radius * std::sin(angle))});
  }
  for (int k = 0; k < segments; ++k)
    disc.triangles.push_back({0, 1 + k, 1 + (k + 1) % segments});
  return disc;
}

void append_part(PathScene& scene, const ch04::Mesh& part, int material) {
  ch04::append_mesh(scene.mesh, part);
  scene.material.insert(scene.material.end(), part.triangles.size(), material);
}

} // namespace

// [listing:build_light_table]
LightTable build_light_table(const PathScene& scene) {
  LightTable table;
  std::vector<double> area_of_material(scene.materials.size(), 0.0);
  std::vector<double> cumulative;
  for (std::size_t k = 0; k < scene.materials.size(); ++k)
    check_emission(scene.materials[k], std::string("#").append(std::to_string(k)));
  for (int i = 0; i < static_cast<int>(scene.mesh.triangles.size()); ++i) {
    const PathMaterial& m = scene.materials[scene.material[i]];
    if (!emits(m)) continue;
    const double area = triangle_area(scene.mesh, i);
    area_of_material[scene.material[i]] += area;
    const double power = area * luminance(m.emission);
    if (!(power > 0.0)) continue; // no area, or a colour the eye weights at zero
    table.triangles.push_back(i);
    table.power += power;
    cumulative.push_back(table.power);
  }
  for (std::size_t k = 0; k < scene.materials.size(); ++k)
    if (emits(scene.materials[k]) && area_of_material[k] == 0.0 &&
        std::count(scene.material.begin(), scene.material.end(), static_cast<int>(k)) > 0)
      throw InputError("emitting material #" + std::to_string(k) +
                       " has triangles of zero area only: it cannot emit any light");
  for (double c : cumulative) table.cdf.push_back(static_cast<float>(c / table.power));
  if (!table.cdf.empty()) table.cdf.back() = 1.0f; // the last pick covers every number < 1
  return table;
}
// [/listing:build_light_table]

PathScene load_path_scene(const std::string& path, long long* defaulted) {
  ch05::ObjMesh obj = ch05::load_obj(path);
  PathScene scene;
  scene.warnings = std::move(obj.warnings);
  scene.materials.push_back(k_default_material); // slot 0; material m of the file is m + 1
  std::map<std::string, std::vector<std::string>> lowered; // MTL file -> materials
  for (const ch05::ObjMaterial& m : obj.materials) {
    bool lowered_here = false;
    scene.materials.push_back(path_material(m, lowered_here));
    if (lowered_here) lowered[m.file].push_back("'" + m.name + "'");
  }
  for (const auto& [file, names] : lowered) {
    std::string list;
    for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
    scene.warnings.push_back(file + ": Kd above " + format_fixed(k_max_albedo, 2) +
                             " lowered to it in " + list +
                             " (a surface that reflects all it receives makes the light of "
                             "a closed room grow without bound)");
  }
  long long without = 0;
  scene.mesh = std::move(obj.geometry);
  for (int id : obj.material_ids) {
    without += id < 0 ? 1 : 0;
    scene.material.push_back(id + 1);
  }
  if (defaulted != nullptr) *defaulted = without;
  scene.lights = build_light_table(scene);
  scene.description = path;
  return scene;
}

CameraSpec frame_from_outside(const ch04::Mesh& mesh, double fov_degrees, Extent extent) {
  CameraSpec camera = ch06::frame_bounds_down_z(ch06::bounds_of(mesh), fov_degrees, extent);
  Vec3d covered{}; // twice the area the triangles cover, projected along x, y and z
  for (int i = 0; i < static_cast<int>(mesh.triangles.size()); ++i) {
    const ch04::TriangleF t = mesh.triangle(i);
    const Vec3d a = t.v0.as<double>();
    covered = covered + elementwise_abs(cross(t.v1.as<double>() - a, t.v2.as<double>() - a));
  }
  if (!(max_component(covered) > 0.0) || covered.z > 1e-3 * max_component(covered))
    return camera;
  const double distance = length(camera.eye - camera.target);
  if (covered.x >= covered.y) {
    camera.eye = camera.target + Vec3d{distance, 0.0, 0.0};
  } else { // from above, the -z axis up the image
    camera.eye = camera.target + Vec3d{0.0, distance, 0.0};
    camera.up = {0.0, 0.0, -1.0};
  }
  return camera;
}

PathScene moving_path_scene(double time, int detail, const ch04::Mesh* model) {
  const ch05::ObjMesh obj = ch10::moving_scene_at(time, detail, model);
  PathScene scene;
  scene.mesh = obj.geometry;
  scene.material = obj.material_ids; // 0 the torus or model, 1 to 4 the spheres, 5 the floor
  scene.materials = {{{0.80f, 0.45f, 0.30f}, {}}, {{0.30f, 0.50f, 0.80f}, {}},
                     {{0.80f, 0.75f, 0.30f}, {}}, {{0.35f, 0.70f, 0.40f}, {}},
                     {{0.75f, 0.30f, 0.60f}, {}}, {{0.60f, 0.60f, 0.60f}, {}}};
  scene.lights = build_light_table(scene);
  scene.description =
      model ? "chapter 10's moving scene with a waving model (" +
                  group_digits(std::ssize(model->triangles)) +
                  " triangles), four orbiting spheres, floor"
            : "chapter 10's moving scene (rippling torus, four orbiting spheres, floor)";
  return scene;
}

CameraSpec cornell_camera() {
  CameraSpec camera;
  camera.eye = {0.0, 1.0, 0.98};
  camera.target = {0.0, 1.12, 0.0}; // tilted up a little: the light in view
  camera.fov_degrees = 78.0;
  return camera;
}

PathScene make_furnace(int subdivisions, float albedo, float emission) {
  PathScene scene;
  scene.materials.push_back({{albedo, albedo, albedo}, {emission, emission, emission}});
  ch04::Mesh sphere = ch04::make_icosphere(subdivisions, {0.0, 0.0, 0.0}, 1.0);
  for (ch04::IndexedTriangle& t : sphere.triangles) std::swap(t.v1, t.v2); // emit inwards
  append_part(scene, sphere, 0);
  scene.lights = build_light_table(scene);
  scene.description = "white furnace: icosphere, albedo " + std::to_string(albedo) +
                      ", emission " + std::to_string(emission);
  return scene;
}

CameraSpec furnace_camera() {
  CameraSpec camera;
  camera.eye = {0.0, 0.0, 0.0};
  camera.target = {0.0, 0.0, -1.0};
  camera.fov_degrees = 90.0;
  return camera;
}

PathScene make_disc_over_floor(float radius, float height, float emission, float albedo,
                               float floor_size, int segments) {
  PathScene scene;
  scene.materials.push_back({{albedo, albedo, albedo}, {0.0f, 0.0f, 0.0f}});
  scene.materials.push_back({{0.0f, 0.0f, 0.0f}, {emission, emission, emission}});
  const double h = floor_size / 2.0;
  ch04::Mesh floor;
  floor.vertices = {{float(-h), 0.0f, float(-h)},
                    {float(h), 0.0f, float(-h)},
                    {float(h), 0.0f, float(h)},
                    {float(-h), 0.0f, float(h)}};
  floor.triangles = {{0, 2, 1}, {0, 3, 2}};
  append_part(scene, floor, 0);
  append_part(scene, make_disc(radius, height, segments), 1);
  scene.lights = build_light_table(scene);
  scene.description = "emitting disc over a white floor";
  return scene;
}

void scale_scene(PathScene& scene, double scale) {
  for (Vec3f& v : scene.mesh.vertices) v = (v.as<double>() * scale).as<float>();
  scene.lights = build_light_table(scene);
}

CameraSpec scaled_camera(CameraSpec camera, double scale) {
  camera.eye = camera.eye * scale;
  camera.target = camera.target * scale;
  return camera;
}

} // namespace rt::ch11
