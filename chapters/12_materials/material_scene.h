// Chapter 12: a scene with materials. Chapter 11's scene (its mesh, its per-triangle material
// numbers, the emission its light table is built from, the sky and the sun) with, beside each
// of its materials, chapter 12's full material; texture coordinates at the corners of every
// triangle; the texture images the materials name; and the camera a glTF file brings.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "material.h"
#include "path_scene.h"
#include "textures.h"

namespace rt::ch12 {

using ch03::CameraSpec;

struct MaterialScene {
  // Chapter 11's scene: path.materials[i].emission is materials[i].emission (the light table
  // is built from it) and path.materials[i].albedo its base colour, for the report.
  ch11::PathScene path;
  std::vector<Material> materials;      // as many as path.materials
  std::vector<std::array<Vec2f, 3>> uv; // per triangle, its corners'; empty: none in the file
  std::vector<TextureImage> textures;   // what the materials' texture indices name
  std::optional<CameraSpec> camera;     // a glTF file's first camera, where it has one
};

// Checks what every loader must hand over: as many materials as path.materials, each checked
// (check_material) and its emission equal to path.materials' one; texture indices in range;
// uv empty or one entry per triangle, every coordinate finite. Throws InputError naming `name`.
void check_material_scene(const MaterialScene& scene, const std::string& name);

} // namespace rt::ch12
