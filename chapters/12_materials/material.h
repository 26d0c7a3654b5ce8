// Chapter 12: what a surface is made of. One record per material, read by the kernels: the
// glTF 2.0 metallic-roughness model (a base colour, how metallic, how rough, an index of
// refraction and how much light it transmits), a conductor given by its complex index of
// refraction (as pbrt gives gold or copper), and chapter 11's Lambertian surface. Textures,
// where a material has them, replace or scale its factors at each hit (textures.h).
#pragma once

#include "rt/hd.h"
#include "rt/vec.h"

namespace rt::ch12 {

enum class MaterialModel : int {
  lambertian,         // chapter 11's: base_color is the albedo, nothing else is read
  metallic_roughness, // glTF 2.0's: a conductor (metallic) over a dielectric (the rest)
  conductor,          // a GGX conductor whose Fresnel term is the exact one of eta + i k
};

inline constexpr int k_no_texture = -1;

// [listing:material]
struct Material {
  MaterialModel model = MaterialModel::lambertian;
  Vec3f base_color{0.8f, 0.8f, 0.8f}; // linear RGB in [0, 1]: albedo, or glTF's base colour
  float metallic = 0.0f;              // [0, 1]: glTF metallicFactor, MTL Pm
  float roughness = 1.0f;             // [0, 1], perceptual: alpha = roughness^2; 0 is smooth
  float ior = 1.5f;                   // the dielectric's index: glTF KHR_materials_ior, MTL Ni
  float transmission = 0.0f;          // [0, 1]: KHR_materials_transmission, MTL Tf / illum 7
  Vec3f emission{};                   // radiance from the front face: Ke, or emissiveFactor
                                      // times KHR_materials_emissive_strength
  Vec3f eta{}, k{};                   // model conductor: the complex index per channel
  Vec3f conductor_f_avg{};            // model conductor: its cosine-weighted mean Fresnel
                                      // (energy_compensation.h), made on the host
  // Indices into the scene's textures, or k_no_texture. base_color: sRGB, multiplies
  // base_color; roughness: its G channel scales roughness; metallic: its B channel scales
  // metallic (glTF's metallicRoughnessTexture is both; MTL's map_Pr and map_Pm are grey
  // images, so any channel serves); emission: sRGB, multiplies emission.
  int base_color_texture = k_no_texture;
  int roughness_texture = k_no_texture;
  int metallic_texture = k_no_texture;
  int emission_texture = k_no_texture;
};
// [/listing:material]

// Below this alpha a surface is smooth: a mirror or a perfectly flat interface, whose lobes
// are delta distributions (a single direction), never found by next-event estimation.
inline constexpr float k_smooth_alpha = 1e-6f;

RT_HD inline float alpha_of(float roughness) { return roughness * roughness; }

} // namespace rt::ch12

#include <string>

namespace rt::ch12 {

// Throws InputError, "<where>: <what is wrong>", for a material the kernels cannot render
// honestly: a factor that is not finite or outside its range (base colour, metallic,
// roughness and transmission in [0, 1], an IOR in [1, 4] (KHR_materials_ior's 0, an
// infinite index, is refused by the glTF loader), emission in [0, ch11::k_max_light], a
// conductor's eta in (0, 10] and k in [0, 20]). `where` names the material and its file.
void check_material(const Material& material, const std::string& where);

} // namespace rt::ch12
