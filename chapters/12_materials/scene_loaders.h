// Chapter 12: scenes with materials from files. Wavefront OBJ with its MTL files (chapter 05's
// loader; the PBR extension's Pm and Pr, and Ni, Tf and illum for glass) and glTF 2.0 (.gltf
// and .glb, read with tinygltf). Both hand over the same MaterialScene, checked, so that one
// room written in either format renders the same image.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "material_scene.h"
#include "obj_loader.h"
#include "textures.h"

namespace rt::ch12 {

// By the file's extension: .obj and .obj.gz are read by load_obj_material_scene, .gltf and
// .glb by load_gltf_material_scene (case does not matter); any other name is a UsageError.
MaterialScene load_material_scene(const std::string& path, const TextureLimits& limits = {});

// [listing:obj_material_rules]
// An OBJ file and its MTL files: chapter 11's scene (load_path_scene: its Kd and Ke checks, its
// default material in slot 0 and the file's material m in slot m + 1, its warnings) with, for
// each MTL material, chapter 12's:
//   Kd -> base_color, Pm -> metallic, Pr -> roughness, Ni -> ior, Ke -> emission;
//   transmission: the mean of Tf where it is above 0, else 1 for `illum 7`, else 0;
//   map_Kd, map_Ke (sRGB) and map_Pr, map_Pm (linear) -> textures, relative to the MTL file.
// A material that gives none of Pm, Pr, Ni, Tf and `illum 7` is chapter 11's Lambertian one
// (its albedo as chapter 11 made it); any other is glTF's metallic-roughness model, with
// glTF's defaults (metallic 0, roughness 1, ior 1.5) for what the MTL file does not give.
// Texture coordinates: OBJ's v runs up the image, the texture module's down (as glTF's), so
// every vt (u, v) becomes (u, 1 - v); corners without a vt get (0, 0).
// A texture file that is missing is one warning (the material keeps its factor); one that is
// there but cannot be decoded is an InputError, as is a Pm, Pr, Ni, Tf or illum statement that
// is not a number.
MaterialScene load_obj_material_scene(const std::string& path,
                                      const TextureLimits& limits = {});
// [/listing:obj_material_rules]

// A glTF 2.0 file, .gltf (JSON, with its buffers and images in files beside it or in data
// URIs) or .glb (binary), whichever the first bytes say. Read: the triangles (mode 4) of every
// mesh of the default scene (or scene 0, or, in a file without scenes, every root node), their
// POSITION and TEXCOORD_0, placed by their nodes' transforms; every material's
// pbrMetallicRoughness, emission (with KHR_materials_emissive_strength), transmission
// (KHR_materials_transmission) and index of refraction (KHR_materials_ior), with their
// textures; the first camera, if a node of the scene carries it. Throws InputError, one line
// naming the file and the problem, for what cannot be read honestly: malformed JSON, missing
// buffers, an accessor outside its buffer view, an index outside its vertices, a type or
// component type the attribute does not allow, numbers that are not finite, a node reached
// twice or more than k_max_gltf_node_depth levels deep (below), counts beyond `load_limits`,
// an extension the file requires that is not one of the three above.
MaterialScene load_gltf_material_scene(const std::string& path,
                                       const TextureLimits& limits = {},
                                       const ch05::LoadLimits& load_limits = {});

// [listing:gltf_instanced]
// The node graph can also be kept instead of flattened: each glTF mesh read once, in its own
// space, and placed by instances, one for every node of the scene that carries it. Rendering
// such a scene (chapter 13) stores a mesh once however often it appears.
struct GltfInstance {
  int mesh;                     // index into GltfInstancedScene::meshes
  std::array<double, 16> world; // the node's world matrix, column-major as glTF stores it:
                                // element (row r, column c) is world[4 c + r]
  int node;                     // the glTF node that places it (for messages)
};

struct GltfMesh {
  ch04::Mesh mesh;                      // in the mesh's own space, as the file gives it
  std::vector<int> material;            // each triangle's slot in GltfInstancedScene::materials
  std::vector<std::array<Vec2f, 3>> uv; // per triangle, its corners'; empty: no TEXCOORD_0
  int gltf_mesh;                        // the glTF mesh it was read from (for messages)
};

// Meshes are numbered in the order the depth-first walk of the nodes first meets them, and
// instances in the order it meets them: the order in which load_gltf_material_scene places
// their triangles, so instance k's triangle t is the flattened scene's triangle (the triangles
// of instances 0 .. k-1) + t, with the same material slot. A mesh that no node of the scene
// drawn carries is left out.
struct GltfInstancedScene {
  std::vector<GltfMesh> meshes;
  std::vector<Material> materials;    // the slots (as MaterialScene::materials)
  std::vector<TextureImage> textures; // what the materials' texture indices name
  std::vector<GltfInstance> instances;
  std::optional<CameraSpec> camera; // as load_gltf_material_scene reads it
  std::vector<std::string> warnings;
  std::string description;
};

// The deepest node graph either glTF loader walks (a root is level 1), and the most instances
// load_gltf_instanced_scene keeps by default. Modelling tools nest a few levels; a chain of
// thousands of nodes is a damaged or hostile file, and each level adds a matrix product's
// rounding to the world matrix. Both are refused in one line naming the file and the node.
inline constexpr int k_max_gltf_node_depth = 64;
inline constexpr long long k_max_gltf_instances = 1LL << 22;

// The same file read as load_gltf_material_scene reads it, with every check it makes (the
// same InputError for the same broken file), except that a mesh is read once, in its own
// space: `load_limits` count the triangles and vertices stored, each mesh once however many
// nodes place it, and the vertices (finite, within ch03::k_max_coordinate) and triangles (a
// triangle with area spans at least ch03::k_min_length) are checked in the mesh's space. The
// world matrices are the nodes' as read, finite, and not checked further: the renderer that
// places meshes by them checks them. More than `max_instances` meshes placed is an InputError.
GltfInstancedScene load_gltf_instanced_scene(const std::string& path,
                                             const TextureLimits& limits = {},
                                             const ch05::LoadLimits& load_limits = {},
                                             long long max_instances = k_max_gltf_instances);
// [/listing:gltf_instanced]

// What both loaders end with: path.materials made from `materials` (albedo the base colour,
// the same emission), the light table built, and check_material_scene run, naming `name`.
void finish_material_scene(MaterialScene& scene, const std::string& name);

// The texture files a scene's materials name, each decoded once per use (sRGB for colours,
// linear for data) into scene.textures. A file that is not there is one warning in
// scene.path.warnings, however many materials name it; one that is there and cannot be read
// throws InputError (load_texture). The limits hold for all the scene's textures together.
class TextureFiles {
public:
  TextureFiles(MaterialScene& scene, const TextureLimits& limits)
      : scene_(scene), limits_(limits) {}
  // The texture's index in scene.textures, or k_no_texture when the file is missing;
  // `named_by` (the material and its file) is what the warning says asked for it.
  int index_of(const std::string& path, bool srgb, const std::string& named_by);

private:
  MaterialScene& scene_;
  TextureLimits limits_;
  std::map<std::pair<std::string, bool>, int> loaded_; // (file, sRGB) -> index
};

} // namespace rt::ch12
