// Chapter 05: triangle meshes from Wavefront OBJ files (plain or gzip-compressed), read with
// tinyobjloader and checked line by line first, so that a hostile or broken file ends in one
// clear error line instead of a crash, a hang or a silently wrong mesh.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "mesh_gen.h"
#include "rt/vec.h"

namespace rt::ch05 {

// What a file may ask for before loading stops with an error. A loader that believes the
// counts it reads can be made to allocate without bound; these caps come first. They are set
// by what the course can promise on a small machine (2 cores, a few GB): a model of 10
// million triangles (a 330 MB grid) takes chapter 07 about 2.1 GB and 17 s to load, build and
// render, and 1 GiB of text is parsed in under a minute. The largest benchmark model has 0.9
// million.
// [listing:load_limits]
struct LoadLimits {
  long long max_triangles = 10'000'000; // after polygons are split into triangles
  long long max_vertices = 10'000'000;  // each of positions, normals, texture coordinates
  long long max_file_bytes = 1LL << 30; // the OBJ text, after gzip decompression
};
// [/listing:load_limits]

// A material of the .mtl files, with the colours a renderer that shades by them reads
// (chapter 11), as tinyobjloader parsed them, and the file that defines it.
struct ObjMaterial {
  std::string name; // `newmtl`
  std::string file; // the .mtl file, as the loader opened it
  Vec3d diffuse;    // Kd (0 where the file gives none)
  Vec3d emission;   // Ke (0 where the file gives none)
  // Empty, or the first Kd or Ke statement of the material whose values are not three finite
  // numbers in the text ("Ke inf 1 1"): tinyobjloader reads what it cannot parse as 0 and a
  // number too large for a double as infinity, so the colours above cannot tell.
  std::string unreadable;

  // What a renderer of physically based materials reads (chapter 12): the PBR extension of
  // MTL (Pm, Pr, map_Pm, map_Pr), the classic statements of glass (Ni, Tf, illum, d) and the
  // texture maps of the colours, as tinyobjloader parsed them. Where the file gives none, the
  // value is tinyobjloader's default, shown after each; the `given` flags below tell the two
  // apart ("Pm 0" and no Pm read alike).
  double metallic = 0.0;         // Pm
  double roughness = 0.0;        // Pr
  double ior = 1.0;              // Ni
  int illum = 0;                 // illum: 7 is refracting glass
  Vec3d transmittance{};         // Tf (or Kt): the colour light keeps passing through
  double dissolve = 1.0;         // d (or 1 - Tr): 1 is opaque
  std::string diffuse_texture;   // map_Kd, the file name as written (relative to `file`)
  std::string roughness_texture; // map_Pr
  std::string metallic_texture;  // map_Pm
  std::string emission_texture;  // map_Ke
  // Which of the statements above the material's text holds, from a scan of the text that
  // also fills `unreadable_pbr` (tinyobjloader cannot tell a default from a value).
  bool has_metallic = false, has_roughness = false, has_ior = false, has_illum = false;
  bool has_transmittance = false, has_dissolve = false;
  // Empty, or the first Pm, Pr, Ni, Tf, Kt, d, Tr or illum statement whose values are not
  // what it takes: one finite number (three for Tf and Kt, an integer for illum).
  std::string unreadable_pbr;
};

// A loaded mesh. Triangle i of `geometry` has corner normals normal_indices[i] and corner
// texture coordinates texcoord_indices[i] (-1 where its face gave none) and material
// material_ids[i]. Indices count from 0, unlike the file's, which count from 1.
struct ObjMesh {
  ch04::Mesh geometry;                                 // positions and their triangles
  std::vector<Vec3f> normals;                          // `vn`; empty when the file has none
  std::vector<ch04::IndexedTriangle> normal_indices;   // per triangle; empty with no normals
  std::vector<Vec2f> texcoords;                        // `vt` (u, v); empty when none
  std::vector<ch04::IndexedTriangle> texcoord_indices; // per triangle; empty with no `vt`
  std::vector<int> material_ids;                       // per triangle; -1: default material
  std::vector<std::string> material_names;             // from the .mtl files, in file order
  int object_count = 0;               // runs of faces under one `o` or `g` name (at least 1)
  int degenerate_triangle_count = 0;  // zero area in float: valid geometry, never hit
  Vec3f bounds_min, bounds_max;       // of the positions that triangles use
  std::vector<ObjMaterial> materials; // material_names' materials, in the same order
  // What loading noticed and let pass, one sentence each that begins with the file it is
  // about: a .mtl file that `mtllib` names and is not there, a `usemtl` name no .mtl file
  // defines, tinyobjloader's notes on the .mtl text. Each only once.
  std::vector<std::string> warnings;
};

// One sentence for a program's --help: what a file may hold (the limits above and the
// supported range of chapter 03), e.g. "at most 10000000 triangles ...".
std::string describe_load_limits(const LoadLimits& limits = {});

// Loads an OBJ file. Gzip-compressed files are recognised by their first two bytes (the gzip
// magic number), whatever the file is called. Materials come from the .mtl files that
// `mtllib` names, looked up next to the OBJ file; a missing .mtl is not an error but a
// warning: faces whose `usemtl` names no loaded material get material id -1. Throws
// rt::InputError with one line, "path:line: what is wrong", for every problem it finds, among
// them what the float pipeline cannot trace (chapter 03's supported_range.h): a coordinate
// beyond +-k_max_coordinate, a triangle with area spanning less than k_min_length, a mesh whose
// triangles are all flat. Loading a large model prints progress lines on stderr
// (rt/cpu_progress.h).
ObjMesh load_obj(const std::string& path, const LoadLimits& limits = {});

// The same from bytes already in memory (OBJ text, or gzip data holding it); errors name
// `name_for_errors`. No file is opened, so `mtllib` is ignored and every material id is -1.
ObjMesh parse_obj(std::string_view bytes, const std::string& name_for_errors,
                  const LoadLimits& limits = {});

} // namespace rt::ch05
