// Chapter 12: an OBJ file with physically based MTL materials. Chapter 11 reads the scene and
// checks its colours; this file adds what chapter 12's materials read (see scene_loaders.h for
// the rules of each MTL statement).
#include <filesystem>
#include <string>

#include "rt/error.h"
#include "scene_loaders.h"

namespace rt::ch12 {

namespace {

float to_float(double value) { return static_cast<float>(value); }

std::string texture_path(const ch05::ObjMaterial& m, const std::string& name) {
  return (std::filesystem::path(m.file).parent_path() / name).string();
}

// [listing:obj_material]
// MTL material `m` as chapter 12's material. `chapter11` is the one chapter 11 made of it: its
// albedo is Kd, checked and, above k_max_albedo, lowered (with the warning chapter 11 gives);
// its emission is Ke, checked.
Material material_of(const ch05::ObjMaterial& m, const ch11::PathMaterial& chapter11,
                     TextureFiles& textures) {
  const std::string where = m.file + ": material '" + m.name + "'";
  if (!m.unreadable_pbr.empty())
    throw InputError(where + ": " + m.unreadable_pbr + ": not the number(s) it takes");
  const Vec3d tf = m.transmittance;
  if (m.has_transmittance && !(min_component(tf) >= 0.0 && max_component(tf) <= 1.0))
    throw InputError(where + ": Tf " + std::to_string(tf.x) + " " + std::to_string(tf.y) + " " +
                     std::to_string(tf.z) + ": a transmittance lies in [0, 1]");
  const bool refracting = m.has_illum && m.illum == 7; // illum 7: glass that refracts
  Material material;
  material.base_color = chapter11.albedo;
  material.emission = chapter11.emission;
  if (m.has_metallic || m.has_roughness || m.has_ior || m.has_transmittance || refracting) {
    material.model = MaterialModel::metallic_roughness;
    material.metallic = m.has_metallic ? to_float(m.metallic) : 0.0f; // glTF's defaults
    material.roughness = m.has_roughness ? to_float(m.roughness) : 1.0f;
    material.ior = m.has_ior ? to_float(m.ior) : 1.5f;
    const double tf_mean = (tf.x + tf.y + tf.z) / 3.0;
    material.transmission = tf_mean > 0.0 ? to_float(tf_mean) : (refracting ? 1.0f : 0.0f);
  }
  const auto texture = [&](const std::string& name, bool srgb) {
    return name.empty()
               ? k_no_texture
               : textures.index_of(texture_path(m, name), srgb, "material '" + m.name + "'");
  };
  material.base_color_texture = texture(m.diffuse_texture, true);
  material.emission_texture = texture(m.emission_texture, true);
  material.roughness_texture = texture(m.roughness_texture, false);
  material.metallic_texture = texture(m.metallic_texture, false);
  check_material(material, where);
  return material;
}
// [/listing:obj_material]

} // namespace

MaterialScene load_obj_material_scene(const std::string& path, const TextureLimits& limits) {
  MaterialScene scene;
  scene.path = ch11::load_path_scene(path);
  // Chapter 11's scene keeps neither the texture coordinates nor the MTL statements it does
  // not read: chapter 05's loader reads the file once more for them. That is the price of
  // calling chapter 11's loader, whose checks of Kd and Ke then hold here unchanged.
  const ch05::ObjMesh obj = ch05::load_obj(path);
  if (obj.geometry.triangles.size() != scene.path.mesh.triangles.size() ||
      obj.materials.size() + 1 != scene.path.materials.size())
    throw InputError(path + ": the file changed while it was read");

  TextureFiles textures(scene, limits);
  scene.materials.push_back({}); // chapter 11's default material: Lambertian, grey 0.8
  scene.materials[0].base_color = scene.path.materials[0].albedo;
  int physically_based = 0;
  for (std::size_t k = 0; k < obj.materials.size(); ++k) {
    scene.materials.push_back(
        material_of(obj.materials[k], scene.path.materials[k + 1], textures));
    physically_based += scene.materials.back().model == MaterialModel::metallic_roughness;
  }

  // [listing:obj_uv_flip]
  // OBJ's v runs up the image, the texture module's down: (u, v) becomes (u, 1 - v).
  if (!obj.texcoords.empty()) {
    scene.uv.resize(obj.texcoord_indices.size());
    for (std::size_t i = 0; i < obj.texcoord_indices.size(); ++i) {
      const ch04::IndexedTriangle& t = obj.texcoord_indices[i];
      const int corners[3] = {t.v0, t.v1, t.v2};
      for (int c = 0; c < 3; ++c) {
        if (corners[c] < 0) continue; // a face without vt: (0, 0)
        const Vec2f vt = obj.texcoords[corners[c]];
        scene.uv[i][c] = {vt.x, 1.0f - vt.y};
      }
    }
  }
  // [/listing:obj_uv_flip]

  scene.path.description = path + ": " + std::to_string(obj.geometry.triangles.size()) +
                           " triangles (" + std::to_string(obj.degenerate_triangle_count) +
                           " of zero area, never hit), " +
                           std::to_string(obj.materials.size()) + " MTL materials (" +
                           std::to_string(physically_based) + " physically based), " +
                           std::to_string(scene.textures.size()) + " textures";
  finish_material_scene(scene, path);
  return scene;
}

} // namespace rt::ch12
