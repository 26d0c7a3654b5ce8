// Chapter 12: what every scene with materials must hold, and the choice of loader by the
// file's name. See material_scene.h and scene_loaders.h.
#include "material_scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "rt/error.h"
#include "scene_loaders.h"

namespace rt::ch12 {

namespace {

bool ends_with_lower(const std::string& path, const std::string& suffix) {
  if (path.size() < suffix.size()) return false;
  std::string tail = path.substr(path.size() - suffix.size());
  std::ranges::transform(tail, tail.begin(),
                         [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return tail == suffix;
}

bool texture_index_valid(int index, std::size_t count) {
  return index == k_no_texture || (index >= 0 && static_cast<std::size_t>(index) < count);
}

} // namespace

void check_material_scene(const MaterialScene& scene, const std::string& name) {
  const ch11::PathScene& path = scene.path;
  if (scene.materials.size() != path.materials.size())
    throw InputError(name + ": " + std::to_string(scene.materials.size()) +
                     " materials for chapter 11's " + std::to_string(path.materials.size()));
  if (path.material.size() != path.mesh.triangles.size())
    throw InputError(name + ": " + std::to_string(path.material.size()) +
                     " material numbers for " + std::to_string(path.mesh.triangles.size()) +
                     " triangles");
  for (std::size_t i = 0; i < path.material.size(); ++i)
    if (path.material[i] < 0 ||
        static_cast<std::size_t>(path.material[i]) >= path.materials.size())
      throw InputError(name + ": triangle " + std::to_string(i) + " has material " +
                       std::to_string(path.material[i]) + " of " +
                       std::to_string(path.materials.size()));
  for (std::size_t k = 0; k < scene.materials.size(); ++k) {
    const Material& m = scene.materials[k];
    const std::string where = name + ": material #" + std::to_string(k);
    check_material(m, where);
    const Vec3f e = path.materials[k].emission;
    if (e.x != m.emission.x || e.y != m.emission.y || e.z != m.emission.z)
      throw InputError(where + ": emission differs from chapter 11's material (the light "
                               "table would sample other lights than the materials show)");
    for (int index :
         {m.base_color_texture, m.roughness_texture, m.metallic_texture, m.emission_texture})
      if (!texture_index_valid(index, scene.textures.size()))
        throw InputError(where + ": texture " + std::to_string(index) + " of " +
                         std::to_string(scene.textures.size()));
  }
  if (!scene.uv.empty() && scene.uv.size() != path.mesh.triangles.size())
    throw InputError(name + ": texture coordinates for " + std::to_string(scene.uv.size()) +
                     " triangles, the mesh has " + std::to_string(path.mesh.triangles.size()));
  for (std::size_t i = 0; i < scene.uv.size(); ++i)
    for (const Vec2f& corner : scene.uv[i])
      if (!std::isfinite(corner.x) || !std::isfinite(corner.y))
        throw InputError(name + ": triangle " + std::to_string(i) +
                         " has a texture coordinate that is not finite");
}

void finish_material_scene(MaterialScene& scene, const std::string& name) {
  scene.path.materials.resize(scene.materials.size());
  for (std::size_t k = 0; k < scene.materials.size(); ++k)
    scene.path.materials[k] = {scene.materials[k].base_color, scene.materials[k].emission};
  check_material_scene(scene, name); // before the light table reads the material numbers
  try {
    scene.path.lights = ch11::build_light_table(scene.path);
  } catch (const InputError& error) { // it names the material, not the file
    throw InputError(name + ": " + error.what());
  }
}

int TextureFiles::index_of(const std::string& path, bool srgb, const std::string& named_by) {
  const auto key = std::make_pair(path, srgb);
  if (const auto found = loaded_.find(key); found != loaded_.end()) return found->second;
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    // Said once per file: the other use, sRGB or linear, finds it missing too.
    if (!loaded_.contains(std::make_pair(path, !srgb)))
      scene_.path.warnings.push_back(path + ": texture file not found (named by " + named_by +
                                     "); its material keeps its factor");
    return loaded_[key] = k_no_texture;
  }
  // What the textures read so far take is subtracted from the limit: the scene's textures
  // together are held to it, and a file over it is refused before it is decoded.
  TextureLimits left = limits_;
  left.max_bytes = limits_.max_bytes - texture_bytes(scene_.textures);
  scene_.textures.push_back(load_texture(path, srgb, left));
  return loaded_[key] = static_cast<int>(scene_.textures.size()) - 1;
}

MaterialScene load_material_scene(const std::string& path, const TextureLimits& limits) {
  if (ends_with_lower(path, ".obj") || ends_with_lower(path, ".obj.gz"))
    return load_obj_material_scene(path, limits);
  if (ends_with_lower(path, ".gltf") || ends_with_lower(path, ".glb"))
    return load_gltf_material_scene(path, limits);
  throw UsageError(path + ": not a scene file of a kind chapter 12 reads (.obj, .obj.gz, "
                          ".gltf or .glb)");
}

} // namespace rt::ch12
