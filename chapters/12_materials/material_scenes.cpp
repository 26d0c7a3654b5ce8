// Chapter 12: scenes made by code. See material_scenes.h.
#include "material_scenes.h"

#include <cmath>

#include "energy_compensation.h"
#include "rt/error.h"

namespace rt::ch12 {

namespace {

// Appends `mesh` to the scene with a new material.
void add_part(MaterialScene& scene, const ch04::Mesh& mesh, const Material& material) {
  ch11::PathScene& s = scene.path;
  const int index = static_cast<int>(scene.materials.size());
  scene.materials.push_back(material);
  s.materials.push_back({material.base_color, material.emission});
  const int base = static_cast<int>(s.mesh.vertices.size());
  s.mesh.vertices.insert(s.mesh.vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
  for (ch04::IndexedTriangle t : mesh.triangles) {
    s.mesh.triangles.push_back({t.v0 + base, t.v1 + base, t.v2 + base});
    s.material.push_back(index);
  }
}

// A rectangle from corner `origin` along `a` and `b` (its front face towards cross(a, b)),
// split into n x n squares of two triangles, each square one of two materials in turn when
// `checkered`.
void add_rectangle(MaterialScene& scene, Vec3d origin, Vec3d a, Vec3d b, int n,
                   const Material& first, const Material* second) {
  ch04::Mesh parts[2];
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      ch04::Mesh& mesh = parts[second != nullptr ? (i + j) % 2 : 0];
      const auto at = [&](int u, int v) {
        return (origin + a * (double(u) / n) + b * (double(v) / n)).as<float>();
      };
      const int base = static_cast<int>(mesh.vertices.size());
      mesh.vertices.insert(mesh.vertices.end(),
                           {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
      mesh.triangles.push_back({base, base + 1, base + 2});
      mesh.triangles.push_back({base, base + 2, base + 3});
    }
  add_part(scene, parts[0], first);
  if (second != nullptr) add_part(scene, parts[1], *second);
}

Material lambertian(float albedo) {
  Material m;
  m.model = MaterialModel::lambertian;
  m.base_color = {albedo, albedo, albedo};
  return m;
}

} // namespace

Material named_material(const std::string& name, float roughness) {
  Material m;
  m.model = MaterialModel::metallic_roughness;
  m.roughness = name == "glass" ? 0.0f : 0.3f;
  if (name == "white") {
    m = lambertian(0.8f);
  } else if (name == "glass" || name == "rough-glass") {
    m.base_color = {1.0f, 1.0f, 1.0f};
    m.transmission = 1.0f;
    m.ior = 1.5f;
  } else if (name == "white-metal") {
    m.base_color = {1.0f, 1.0f, 1.0f};
    m.metallic = 1.0f;
  } else if (name == "plastic") {
    m.base_color = {0.8f, 0.1f, 0.1f};
  } else if (name == "gold" || name == "copper") {
    // The complex index at about 650, 550 and 450 nm (Johnson and Christy 1972's data).
    m.model = MaterialModel::conductor;
    m.base_color = {1.0f, 1.0f, 1.0f};
    if (name == "gold") {
      m.eta = {0.143f, 0.374f, 1.442f};
      m.k = {3.983f, 2.385f, 1.603f};
    } else {
      m.eta = {0.200f, 0.924f, 1.102f};
      m.k = {3.912f, 2.452f, 2.142f};
    }
    m.conductor_f_avg = conductor_f_avg(m.eta, m.k);
  } else {
    throw UsageError("unknown material '" + name + "' (" + material_names() + ")");
  }
  if (name != "white" && roughness >= 0.0f) m.roughness = roughness;
  return m;
}

std::string material_names() {
  return "white, glass, rough-glass, white-metal, plastic, gold or copper";
}

MaterialScene make_sphere_in_sky(const Material& material, int subdivisions, float sky) {
  MaterialScene scene;
  add_part(scene, ch04::make_icosphere(subdivisions, {0.0, 0.0, 0.0}, 1.0), material);
  scene.path.environment.sky = {sky, sky, sky};
  scene.path.lights = ch11::build_light_table(scene.path);
  scene.path.description = "a sphere of " + std::to_string(20 << (2 * subdivisions)) +
                           " triangles under a uniform sky of radiance " + std::to_string(sky);
  check_material_scene(scene, "the sphere in the sky");
  return scene;
}

CameraSpec sphere_camera() {
  CameraSpec camera;
  camera.eye = {0.0, 0.0, 4.0};
  camera.target = {0.0, 0.0, 0.0};
  camera.fov_degrees = 30.0;
  return camera;
}

MaterialScene make_roughness_series(const Material& material) {
  MaterialScene scene;
  const Material floor = lambertian(0.5f);
  const Material dark = lambertian(0.05f), light = lambertian(0.7f);
  add_rectangle(scene, {-8.0, 0.0, 6.0}, {16.0, 0.0, 0.0}, {0.0, 0.0, -12.0}, 1, floor,
                nullptr);
  add_rectangle(scene, {-8.0, 0.0, -3.0}, {16.0, 0.0, 0.0}, {0.0, 8.0, 0.0}, 16, dark, &light);
  const float roughness[] = {0.0f, 0.1f, 0.25f, 0.5f, 1.0f};
  for (int i = 0; i < 5; ++i) {
    Material m = material;
    if (m.model != MaterialModel::lambertian) m.roughness = roughness[i];
    add_part(scene, ch04::make_icosphere(5, {-4.4 + 2.2 * i, 1.0, 0.0}, 1.0), m);
  }
  ch11::Environment& e = scene.path.environment;
  e.sky = {0.3f, 0.3f, 0.3f};
  e.sun_direction = normalize(Vec3f{0.4f, 1.0f, 0.6f});
  e.sun_irradiance = {2.0f, 1.9f, 1.7f};
  scene.path.lights = ch11::build_light_table(scene.path);
  scene.path.description = "five spheres, roughness 0, 0.1, 0.25, 0.5 and 1";
  check_material_scene(scene, "the roughness series");
  return scene;
}

CameraSpec roughness_series_camera() {
  CameraSpec camera;
  camera.eye = {0.0, 2.6, 9.0};
  camera.target = {0.0, 1.0, 0.0};
  camera.fov_degrees = 36.0;
  return camera;
}

} // namespace rt::ch12
