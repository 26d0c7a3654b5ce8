// Chapter 11: scenes for light transport. See path_scene.h.
#include "path_scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include <tiny_obj_loader.h>

#include "animation.h"
#include "gunzip.h"
#include "obj_loader.h"
#include "path_sampling.h"
#include "rt/error.h"

namespace rt::ch11 {
namespace {

constexpr PathMaterial k_default_material{{0.8f, 0.8f, 0.8f}, {0.0f, 0.0f, 0.0f}};
constexpr float k_max_albedo = 0.99f;

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

// The bytes of a file, unpacked when it is gzip data (chapter 05's rule).
std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  std::string text = bytes.str();
  return ch05::is_gzip(text) ? ch05::gunzip(text, path, 1LL << 30) : text;
}

// Every material of the MTL files the OBJ file's `mtllib` lines name, by name. Chapter 05's
// loader reads the same files for the names alone; Kd and Ke are read here.
std::map<std::string, PathMaterial> read_mtl_materials(const std::string& obj_path) {
  const std::filesystem::path folder = std::filesystem::path(obj_path).parent_path();
  std::istringstream lines(read_text(obj_path));
  std::map<std::string, PathMaterial> by_name;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string keyword, file;
    if (!(words >> keyword) || keyword != "mtllib") continue;
    while (words >> file) {
      std::ifstream mtl(folder / file);
      if (!mtl) continue; // a missing MTL file: its faces get the default material
      std::map<std::string, int> index;
      std::vector<tinyobj::material_t> materials;
      std::string warnings, errors;
      tinyobj::LoadMtl(&index, &materials, &mtl, &warnings, &errors);
      for (const tinyobj::material_t& m : materials) {
        const auto f = [](double v) { return static_cast<float>(v); };
        const Vec3f kd{f(m.diffuse[0]), f(m.diffuse[1]), f(m.diffuse[2])};
        const auto clamp_albedo = [](float v) {
          return std::isfinite(v) ? std::clamp(v, 0.0f, k_max_albedo) : 0.0f;
        };
        PathMaterial material{{clamp_albedo(kd.x), clamp_albedo(kd.y), clamp_albedo(kd.z)},
                              {f(m.emission[0]), f(m.emission[1]), f(m.emission[2])}};
        check_emission(material, m.name);
        by_name.emplace(m.name, material);
      }
    }
  }
  return by_name;
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
  const ch05::ObjMesh obj = ch05::load_obj(path);
  const std::map<std::string, PathMaterial> mtl = read_mtl_materials(path);
  PathScene scene;
  scene.mesh = obj.geometry;
  scene.materials.push_back(k_default_material); // slot 0
  std::vector<int> slot_of_material(obj.material_names.size(), 0);
  for (std::size_t m = 0; m < obj.material_names.size(); ++m) {
    const auto found = mtl.find(obj.material_names[m]);
    if (found == mtl.end()) continue;
    slot_of_material[m] = static_cast<int>(scene.materials.size());
    scene.materials.push_back(found->second);
  }
  long long without = 0;
  for (int id : obj.material_ids) {
    const int slot = id < 0 ? 0 : slot_of_material[id];
    without += slot == 0 ? 1 : 0;
    scene.material.push_back(slot);
  }
  if (defaulted != nullptr) *defaulted = without;
  scene.lights = build_light_table(scene);
  scene.description = path;
  return scene;
}

PathScene moving_path_scene(double time, int detail) {
  const ch05::ObjMesh obj = ch10::moving_scene_at(time, detail);
  PathScene scene;
  scene.mesh = obj.geometry;
  scene.material = obj.material_ids; // 0 the torus, 1 to 4 the spheres, 5 the floor
  scene.materials = {{{0.80f, 0.45f, 0.30f}, {}}, {{0.30f, 0.50f, 0.80f}, {}},
                     {{0.80f, 0.75f, 0.30f}, {}}, {{0.35f, 0.70f, 0.40f}, {}},
                     {{0.75f, 0.30f, 0.60f}, {}}, {{0.60f, 0.60f, 0.60f}, {}}};
  scene.lights = build_light_table(scene);
  scene.description =
      "chapter 10's moving scene (rippling torus, four orbiting spheres, floor)";
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
