// Chapter 05: the OBJ loader. See obj_loader.h.
//
// Loading takes four steps:
//   1. Bytes: the file is read with a size cap; gzip data is unpacked, also capped (gunzip.h).
//   2. Line checks: every statement the mesh depends on is checked, with its line number, and
//      the statements it does not use are blanked out (obj_checks.h).
//   3. tinyobjloader parses what is left, which is now known to be well formed.
//   4. Conversion: polygons become fans of triangles; every index is checked once more.
#include "obj_loader.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <istream>
#include <map>
#include <memory>
#include <set>
#include <streambuf>
#include <string_view>
#include <system_error>
#include <utility>

#include <tiny_obj_loader.h>

#include "gunzip.h"
#include "obj_checks.h"
#include "rt/cpu_progress.h"
#include "rt/error.h"
#include "supported_range.h"

namespace rt::ch05 {

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw InputError(name + ": " + what);
}

// The line checks promise tinyobjloader only text it reads correctly. If the two ever disagree
// the mesh cannot be trusted, so loading stops (the fuzzer treats this message as a bug).
[[noreturn]] void disagreement(const std::string& name, const std::string& what) {
  fail(name, "tinyobjloader disagrees with the line checks: " + what);
}

// ---------------------------------------------------------------------------------------------
// Step 1: bytes.

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

[[noreturn]] void fail_too_large(const std::string& name, long long max_bytes) {
  fail(name,
       "larger than LoadLimits::max_file_bytes (" + std::to_string(max_bytes) + " bytes)");
}

// Reads all of `file`, failing as soon as it holds more than max_bytes. The size the file
// system reports is not trusted: a file can grow while it is read.
std::string read_all(std::FILE* file, long long max_bytes, const std::string& name) {
  std::string bytes;
  std::array<char, 1 << 16> chunk{};
  for (;;) {
    const std::size_t got = std::fread(chunk.data(), 1, chunk.size(), file);
    if (static_cast<long long>(bytes.size() + got) > max_bytes) fail_too_large(name, max_bytes);
    bytes.append(chunk.data(), got);
    if (got < chunk.size()) break;
  }
  if (std::ferror(file)) fail(name, std::string("read error (") + std::strerror(errno) + ")");
  return bytes;
}

// A directory or a device is refused before it is opened: reading /dev/zero never ends, and
// opening a named pipe waits for a writer that may never come.
std::string read_obj_file(const std::string& path, const LoadLimits& limits) {
  namespace fs = std::filesystem;
  if (path.empty()) throw InputError("the OBJ file name is empty");
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error) fail(path, "cannot open (" + error.message() + ")");
  if (fs::is_directory(status)) fail(path, "is a directory, not an OBJ file");
  if (!fs::is_regular_file(status)) fail(path, "is not a regular file");
  // A size above the limit is believed at once (reading 100 GB to find out would take long).
  const std::uintmax_t size = fs::file_size(path, error);
  if (!error && size > static_cast<std::uintmax_t>(std::max(limits.max_file_bytes, 0LL))) {
    fail_too_large(path, limits.max_file_bytes);
  }
  const File file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  return read_all(file.get(), limits.max_file_bytes, path);
}

// ---------------------------------------------------------------------------------------------
// Step 3: tinyobjloader.

// tinyobjloader reads from an std::istream. This one reads the text where it already is (an
// std::istringstream would first copy a file that may be gigabytes long), a window at a time,
// so that each move to the next window can say how far reading has come.
class TextStreamBuffer : public std::streambuf {
public:
  explicit TextStreamBuffer(std::string_view text,
                            std::function<void(std::size_t)> read_up_to = {})
      : end_(const_cast<char*>(text.data() + text.size())), read_up_to_(std::move(read_up_to)) {
    // The get area is only read from: the const_cast never leads to a write.
    char* begin = const_cast<char*>(text.data());
    setg(begin, begin, begin + std::min<std::size_t>(text.size(), k_window));
  }

private:
  static constexpr std::size_t k_window = 1 << 20;

  int_type underflow() override {
    if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
    if (egptr() == end_) return traits_type::eof();
    if (read_up_to_) read_up_to_(static_cast<std::size_t>(egptr() - eback()));
    setg(eback(), egptr(), egptr() + std::min<std::size_t>(end_ - egptr(), k_window));
    return traits_type::to_int_type(*gptr());
  }

  char* end_;
  std::function<void(std::size_t)> read_up_to_;
};

// True when `text` is a decimal number as tinyobjloader reads one whole ("-1.5e3", ".5", "2.")
// and finite as a double: "inf", "nan", "0x10", "1e400" and "5abc" are not.
bool is_finite_decimal(std::string_view text) {
  std::size_t i = 0, digits = 0;
  const auto skip_digits = [&] {
    const std::size_t from = i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
    return i - from;
  };
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
  digits += skip_digits();
  if (i < text.size() && text[i] == '.') {
    ++i;
    digits += skip_digits();
  }
  if (digits == 0) return false;
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    if (skip_digits() == 0) return false;
  }
  return i == text.size() && std::isfinite(std::strtod(std::string(text).c_str(), nullptr));
}

// True when `text` is a decimal integer as tinyobjloader reads one ("7", "-2"), of at most
// nine digits (an int holds it).
bool is_decimal_integer(std::string_view text) {
  if (!text.empty() && (text[0] == '+' || text[0] == '-')) text.remove_prefix(1);
  return !text.empty() && text.size() <= 9 &&
         std::ranges::all_of(text, [](char c) { return c >= '0' && c <= '9'; });
}

// What the statements of one material in an .mtl text say that tinyobjloader's numbers hide:
// the first Kd or Ke that is not three finite numbers, the first statement of the PBR and
// glass values (Pm, Pr, Ni, Tf or Kt, d or Tr, illum) whose values are not what it takes, and
// which of those values the text gives at all.
struct MaterialStatements {
  std::string unreadable, unreadable_pbr;
  bool has_metallic = false, has_roughness = false, has_ior = false, has_illum = false;
  bool has_transmittance = false, has_dissolve = false;
};

// The statements of every material of an .mtl text, by the material's name as tinyobjloader
// reads it (lines end at \n, \r or both; the name is the rest of the `newmtl` line after one
// blank, trailing blanks cut). Statements before the first `newmtl` belong to no material.
std::map<std::string, MaterialStatements> scan_material_statements(std::string_view text) {
  std::map<std::string, MaterialStatements> found;
  MaterialStatements* material = nullptr;
  while (!text.empty()) {
    const std::size_t end = std::min(text.find_first_of("\r\n"), text.size());
    std::string_view line = text.substr(0, end);
    text.remove_prefix(std::min(end + 1, text.size()));
    line.remove_suffix(line.size() - std::min(line.find_last_not_of(" \t") + 1, line.size()));
    line.remove_prefix(std::min(line.find_first_not_of(" \t"), line.size()));
    const auto is_blank = [](char c) { return c == ' ' || c == '\t'; };
    if (line.size() > 6 && line.starts_with("newmtl") && is_blank(line[6])) {
      material = &found[std::string(line.substr(7))];
      continue;
    }
    const std::size_t keyword_end = std::min(line.find_first_of(" \t"), line.size());
    const std::string_view keyword = line.substr(0, keyword_end);
    if (material == nullptr || keyword_end == line.size()) continue;
    std::vector<std::string_view> values;
    for (std::string_view rest = line.substr(keyword_end); !rest.empty();) {
      rest.remove_prefix(std::min(rest.find_first_not_of(" \t"), rest.size()));
      const std::size_t length = std::min(rest.find_first_of(" \t"), rest.size());
      if (length > 0) values.push_back(rest.substr(0, length));
      rest.remove_prefix(length);
    }
    const auto numbers = [&](std::size_t count) {
      return values.size() == count && std::ranges::all_of(values, is_finite_decimal);
    };
    bool readable = true;
    if (keyword == "Kd" || keyword == "Ke") {
      if (material->unreadable.empty() && !numbers(3)) material->unreadable = std::string(line);
      continue;
    }
    if (keyword == "Pm") {
      material->has_metallic = true;
      readable = numbers(1);
    } else if (keyword == "Pr") {
      material->has_roughness = true;
      readable = numbers(1);
    } else if (keyword == "Ni") {
      material->has_ior = true;
      readable = numbers(1);
    } else if (keyword == "Tf" || keyword == "Kt") {
      material->has_transmittance = true;
      readable = numbers(3);
    } else if (keyword == "d" || keyword == "Tr") {
      material->has_dissolve = true;
      readable = numbers(1);
    } else if (keyword == "illum") {
      material->has_illum = true;
      readable = values.size() == 1 && is_decimal_integer(values[0]);
    }
    if (!readable && material->unreadable_pbr.empty())
      material->unreadable_pbr = std::string(line);
  }
  return found;
}

// Reads the .mtl files that `mtllib` names, from the OBJ file's folder. tinyobjloader asks for
// each name once; "false" means not found, and it then carries on without those materials,
// so the faces that use them get material id -1. That is this chapter's rule for a missing
// .mtl: the geometry is still right, and a renderer can draw those faces in a default material;
// the reader is told, in a warning. Each material is kept with its file and with what the
// text holds that tinyobjloader's numbers hide (ObjMaterial::unreadable, unreadable_pbr and
// the `has_` flags).
class MaterialFolder final : public tinyobj::MaterialReader {
public:
  MaterialFolder(std::filesystem::path folder, std::string obj_name, const LoadLimits& limits)
      : folder_(std::move(folder)), obj_name_(std::move(obj_name)), limits_(limits) {}

  bool operator()(const std::string& file, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* names, std::string* /*warnings*/,
                  std::string* errors) override {
    namespace fs = std::filesystem;
    const fs::path path = folder_ / file;
    std::error_code error;
    if (!fs::is_regular_file(path, error)) return missing(file, path);
    fs::path same_file = fs::weakly_canonical(path, error);
    if (error) same_file = path;
    if (!loaded_.insert(same_file).second) return true; // named twice, loaded once
    const File stream_file(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!stream_file) return missing(file, path);
    const std::string text = read_all(stream_file.get(), limits_.max_file_bytes, path.string());
    TextStreamBuffer buffer(text);
    std::istream stream(&buffer);
    const std::size_t first = materials->size();
    std::string notes;
    tinyobj::LoadMtl(names, materials, &stream, &notes, errors);
    add_lines(warnings_, path.string(), notes);
    const std::map<std::string, MaterialStatements> statements = scan_material_statements(text);
    for (std::size_t k = first; k < materials->size(); ++k)
      materials_.push_back(obj_material((*materials)[k], path.string(), statements));
    return true;
  }

  std::vector<ObjMaterial>& materials() { return materials_; }
  std::vector<std::string>& warnings() { return warnings_; }

  // Each line of `text` as a warning about `file`.
  static void add_lines(std::vector<std::string>& warnings, const std::string& file,
                        std::string_view text) {
    while (!text.empty()) {
      const std::size_t end = std::min(text.find('\n'), text.size());
      if (const std::string_view line = text.substr(0, end); !line.empty())
        warnings.push_back(file + ": " + std::string(line));
      text.remove_prefix(std::min(end + 1, text.size()));
    }
  }

private:
  static ObjMaterial obj_material(const tinyobj::material_t& m, const std::string& file,
                                  const std::map<std::string, MaterialStatements>& statements) {
    ObjMaterial material;
    material.name = m.name;
    material.file = file;
    material.diffuse = {m.diffuse[0], m.diffuse[1], m.diffuse[2]};
    material.emission = {m.emission[0], m.emission[1], m.emission[2]};
    material.metallic = m.metallic;
    material.roughness = m.roughness;
    material.ior = m.ior;
    material.illum = m.illum;
    material.transmittance = {m.transmittance[0], m.transmittance[1], m.transmittance[2]};
    material.dissolve = m.dissolve;
    material.diffuse_texture = m.diffuse_texname;
    material.roughness_texture = m.roughness_texname;
    material.metallic_texture = m.metallic_texname;
    material.emission_texture = m.emissive_texname;
    if (const auto found = statements.find(m.name); found != statements.end()) {
      const MaterialStatements& s = found->second;
      material.unreadable = s.unreadable;
      material.unreadable_pbr = s.unreadable_pbr;
      material.has_metallic = s.has_metallic;
      material.has_roughness = s.has_roughness;
      material.has_ior = s.has_ior;
      material.has_illum = s.has_illum;
      material.has_transmittance = s.has_transmittance;
      material.has_dissolve = s.has_dissolve;
    }
    return material;
  }

  bool missing(const std::string& file, const std::filesystem::path& path) {
    warnings_.push_back(obj_name_ + ": mtllib " + file + ": no such file (" + path.string() +
                        "); the faces that use its materials get the default material");
    return false;
  }

  std::filesystem::path folder_;
  std::string obj_name_;
  LoadLimits limits_;
  std::set<std::filesystem::path> loaded_;
  std::vector<ObjMaterial> materials_; // tinyobjloader's materials, in its order
  std::vector<std::string> warnings_;
};

// ---------------------------------------------------------------------------------------------
// Step 4: conversion.

// tinyobjloader's doubles, rounded to float. The line checks let only numbers through that
// are finite as floats; a non-finite one here would mean the two readers differ.
float to_float(tinyobj::real_t x, const std::string& name) {
  const auto f = static_cast<float>(x);
  if (!ch04::is_finite(f)) disagreement(name, "a number that is not finite as a float");
  return f;
}

std::vector<Vec3f> to_vec3f(const std::vector<tinyobj::real_t>& xyz, const std::string& name) {
  std::vector<Vec3f> out(xyz.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = {to_float(xyz[3 * i], name), to_float(xyz[3 * i + 1], name),
              to_float(xyz[3 * i + 2], name)};
  }
  return out;
}

// Appends the triangles of a mesh, checking every index that tinyobjloader gives against the
// arrays it indexes: after the line checks none can be out of range, and this makes sure.
class MeshBuilder {
public:
  MeshBuilder(ObjMesh& mesh, int material_count, const std::string& name)
      : mesh_(mesh), positions_(static_cast<int>(mesh.geometry.vertices.size())),
        normals_(static_cast<int>(mesh.normals.size())),
        texcoords_(static_cast<int>(mesh.texcoords.size())), materials_(material_count),
        name_(name) {}

  // [listing:mesh_builder_add]
  // One triangle of corners a, b, c (tinyobjloader's 0-based indices, -1 where absent).
  void add(const tinyobj::index_t& a, const tinyobj::index_t& b, const tinyobj::index_t& c,
           int material) {
    mesh_.geometry.triangles.push_back({checked(a.vertex_index, positions_, false),
                                        checked(b.vertex_index, positions_, false),
                                        checked(c.vertex_index, positions_, false)});
    if (normals_ > 0) {
      mesh_.normal_indices.push_back({checked(a.normal_index, normals_, true),
                                      checked(b.normal_index, normals_, true),
                                      checked(c.normal_index, normals_, true)});
    }
    if (texcoords_ > 0) {
      mesh_.texcoord_indices.push_back({checked(a.texcoord_index, texcoords_, true),
                                        checked(b.texcoord_index, texcoords_, true),
                                        checked(c.texcoord_index, texcoords_, true)});
    }
    mesh_.material_ids.push_back(checked(material, materials_, true));
  }
  // [/listing:mesh_builder_add]

private:
  int checked(int index, int count, bool may_be_absent) const {
    if ((index >= 0 && index < count) || (may_be_absent && index == -1)) return index;
    disagreement(name_, "index " + std::to_string(index) + " of " + std::to_string(count));
  }

  ObjMesh& mesh_;
  int positions_, normals_, texcoords_, materials_; // sizes of the arrays indexed
  const std::string& name_;
};

ObjMesh convert(const tinyobj::attrib_t& attrib, const std::vector<tinyobj::shape_t>& shapes,
                const std::vector<tinyobj::material_t>& materials, const ObjCounts& counts,
                const std::string& name) {
  ObjMesh mesh;
  mesh.geometry.vertices = to_vec3f(attrib.vertices, name);
  mesh.normals = to_vec3f(attrib.normals, name);
  mesh.texcoords.resize(attrib.texcoords.size() / 2);
  for (std::size_t i = 0; i < mesh.texcoords.size(); ++i) {
    mesh.texcoords[i] = {to_float(attrib.texcoords[2 * i], name),
                         to_float(attrib.texcoords[2 * i + 1], name)};
  }
  if (static_cast<long long>(mesh.geometry.vertices.size()) != counts.positions ||
      static_cast<long long>(mesh.normals.size()) != counts.normals ||
      static_cast<long long>(mesh.texcoords.size()) != counts.texcoords) {
    disagreement(name, "vertex, normal or texture coordinate count");
  }
  for (const tinyobj::material_t& material : materials) {
    mesh.material_names.push_back(material.name);
  }

  // Polygons become fans around their first corner: (0 1 2), (0 2 3), (0 3 4)... Exact for
  // the convex polygons exporters write (a quad, a pentagon); a concave polygon would need
  // ear clipping instead. tinyobjloader can triangulate, but by ear clipping that may drop
  // pieces of degenerate polygons without a word, so it is asked for the polygons as they are.
  const auto triangle_count = static_cast<std::size_t>(counts.triangles);
  mesh.geometry.triangles.reserve(triangle_count);
  mesh.material_ids.reserve(triangle_count);
  if (!mesh.normals.empty()) mesh.normal_indices.reserve(triangle_count);
  if (!mesh.texcoords.empty()) mesh.texcoord_indices.reserve(triangle_count);
  MeshBuilder builder(mesh, static_cast<int>(materials.size()), name);
  long long face_number = 0;
  std::size_t next_large = 0;
  for (const tinyobj::shape_t& shape : shapes) {
    const tinyobj::mesh_t& polygons = shape.mesh;
    if (polygons.material_ids.size() != polygons.num_face_vertices.size()) {
      disagreement(name, "one material id per face");
    }
    std::size_t first = 0; // of the current face's corners in polygons.indices
    for (std::size_t face = 0; face < polygons.num_face_vertices.size(); ++face) {
      std::size_t corners = polygons.num_face_vertices[face];
      if (next_large < counts.large_faces.size() &&
          counts.large_faces[next_large].first == face_number) {
        const auto counted = static_cast<std::size_t>(counts.large_faces[next_large++].second);
        if (counted % 256 != corners) disagreement(name, "corners of a large face");
        corners = counted;
      }
      if (corners < 3 || first + corners > polygons.indices.size()) {
        disagreement(name, "corners of face " + std::to_string(face_number + 1));
      }
      const tinyobj::index_t* corner = polygons.indices.data() + first;
      for (std::size_t k = 1; k + 1 < corners; ++k) {
        builder.add(corner[0], corner[k], corner[k + 1], polygons.material_ids[face]);
      }
      first += corners;
      ++face_number;
    }
    if (first != polygons.indices.size()) disagreement(name, "corners left over");
  }
  if (face_number != counts.faces) {
    disagreement(name, std::to_string(face_number) + " faces, the checks counted " +
                           std::to_string(counts.faces));
  }
  mesh.object_count = static_cast<int>(shapes.size());

  mesh.bounds_min = mesh.bounds_max = mesh.geometry.vertices[mesh.geometry.triangles[0].v0];
  for (std::size_t i = 0; i < mesh.geometry.triangles.size(); ++i) {
    const ch04::TriangleF t = mesh.geometry.triangle(static_cast<int>(i));
    for (const Vec3f& p : {t.v0, t.v1, t.v2}) {
      mesh.bounds_min = elementwise_min(mesh.bounds_min, p);
      mesh.bounds_max = elementwise_max(mesh.bounds_max, p);
    }
    // Repeated corners and collinear corners alike give an exactly zero cross product: valid
    // geometry that is never hit. A triangle with area must be large enough for float's
    // products (chapter 03's supported_range.h).
    if (ch04::is_flat(t)) {
      ++mesh.degenerate_triangle_count;
    } else if (const double span = ch04::triangle_span(t); span < ch03::k_min_length) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "triangle %zu spans only %.3g; a triangle with area must span at least %g "
                    "(the smallest scale the float pipeline supports)",
                    i, span, ch03::k_min_length);
      fail(name, text);
    }
  }
  // A mesh of flat triangles only is refused like a mesh of no faces: nothing would be drawn.
  if (mesh.degenerate_triangle_count == static_cast<int>(mesh.geometry.triangles.size())) {
    fail(name, "all " + std::to_string(mesh.degenerate_triangle_count) +
                   " triangles are flat (zero area in float): nothing to intersect");
  }
  return mesh;
}

ObjMesh parse_text(std::string text, const std::string& name, const LoadLimits& limits,
                   MaterialFolder* material_folder) {
  if (text.empty()) fail(name, "the file is empty");
  // A model of millions of triangles takes seconds to check and to parse: both say how far
  // they have come (rt/cpu_progress.h), as one piece of work of twice the text's size.
  const CpuWorkName work("loading " + name);
  CpuProgress progress(2 * static_cast<long long>(text.size()), nullptr);
  const ObjCounts counts = check_obj_lines(text, name, limits, [&](std::size_t offset) {
    progress.update(static_cast<long long>(offset));
  });
  if (counts.faces == 0) {
    fail(name, "no faces (" + std::to_string(counts.positions) +
                   (counts.positions == 1 ? " vertex" : " vertices") +
                   "): nothing to intersect");
  }

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warnings;
  {
    TextStreamBuffer buffer(text, [&](std::size_t offset) {
      progress.update(static_cast<long long>(text.size() + offset));
    });
    std::istream stream(&buffer);
    std::string errors;
    // Polygons are kept whole (triangulate = false, see convert()); per-vertex colours, an
    // extension this course does not use, are not stored (default_vcols_fallback = false).
    // After the line checks its warnings can only be about materials: they are passed on.
    if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warnings, &errors, &stream,
                          material_folder, false, false)) {
      disagreement(name, errors.substr(0, std::min<std::size_t>(errors.find('\n'), 120)));
    }
  }
  text = std::string(); // no longer needed: its memory goes back before the mesh is built
  ObjMesh mesh = convert(attrib, shapes, materials, counts, name);
  if (material_folder != nullptr) {
    mesh.materials = std::move(material_folder->materials());
    if (mesh.materials.size() != mesh.material_names.size())
      disagreement(name, "materials read from the .mtl files");
    mesh.warnings = std::move(material_folder->warnings());
  }
  // The folder's warning names the missing file; tinyobjloader's general one adds nothing.
  const std::string general = "Failed to load material file(s). Use default material.\n";
  for (std::size_t at; (at = warnings.find(general)) != std::string::npos;)
    warnings.erase(at, general.size());
  MaterialFolder::add_lines(mesh.warnings, name, warnings);
  std::set<std::string> seen; // a `usemtl` of a missing material warns at every use
  std::erase_if(mesh.warnings, [&](const std::string& w) { return !seen.insert(w).second; });
  return mesh;
}

} // namespace

std::string describe_load_limits(const LoadLimits& limits) {
  char text[320];
  std::snprintf(text, sizeof text,
                "OBJ files (plain or gzip'd) hold at most %lld triangles and %lld vertices in "
                "%lld bytes of text; coordinates within +-%g; a triangle with area spans at "
                "least %g (book chapters 03 and 05).",
                limits.max_triangles, limits.max_vertices, limits.max_file_bytes,
                ch03::k_max_coordinate, ch03::k_min_length);
  return text;
}

ObjMesh load_obj(const std::string& path, const LoadLimits& limits) {
  std::string bytes = read_obj_file(path, limits);
  if (is_gzip(bytes)) bytes = gunzip(bytes, path, limits.max_file_bytes);
  MaterialFolder materials(std::filesystem::path(path).parent_path(), path, limits);
  return parse_text(std::move(bytes), path, limits, &materials);
}

ObjMesh parse_obj(std::string_view bytes, const std::string& name_for_errors,
                  const LoadLimits& limits) {
  if (is_gzip(bytes)) {
    return parse_text(gunzip(bytes, name_for_errors, limits.max_file_bytes), name_for_errors,
                      limits, nullptr);
  }
  if (static_cast<long long>(bytes.size()) > limits.max_file_bytes) {
    fail_too_large(name_for_errors, limits.max_file_bytes);
  }
  return parse_text(std::string(bytes), name_for_errors, limits, nullptr);
}

} // namespace rt::ch05
