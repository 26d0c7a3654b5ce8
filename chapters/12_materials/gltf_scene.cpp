// Chapter 12: glTF 2.0 scenes. tinygltf (Debian's libtinygltf-dev) parses the JSON, decodes
// the data URIs and reads the buffers; everything it leaves unchecked is checked here before a
// byte of a buffer is read: every index into an array, every accessor against its buffer view
// and every view against its buffer, every count against chapter 05's limits. Images are
// decoded by the texture module (files) or by stb_image (bytes inside the glTF file), never
// by tinygltf. See scene_loaders.h for what is read.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE       // images are decoded below, after their sizes are checked
#define TINYGLTF_NO_STB_IMAGE_WRITE // nothing is written
#define TINYGLTF_NO_EXTERNAL_IMAGE  // image files are read by the texture module
#include <tiny_gltf.h>

#include <stb_image.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "rt/error.h"
#include "scene_loaders.h"
#include "supported_range.h"

namespace rt::ch12 {

namespace {

static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian");

namespace fs = std::filesystem;

// The extensions a file may require: the three this loader reads. Any other required one
// changes what the file means (compressed geometry, another material model), so it is refused.
const std::set<std::string> k_supported_required = {
    "KHR_materials_emissive_strength", "KHR_materials_ior", "KHR_materials_transmission"};

// glTF's default material, for primitives that name none: the schema's defaults of
// pbrMetallicRoughness (white, metallic 1, roughness 1).
Material default_gltf_material() {
  Material m;
  m.model = MaterialModel::metallic_roughness;
  m.base_color = {1.0f, 1.0f, 1.0f};
  m.metallic = 1.0f;
  m.roughness = 1.0f;
  return m;
}

// A 4 x 4 matrix, column-major as glTF stores it: element (row r, column c) is m[4 c + r].
using Matrix = std::array<double, 16>;

constexpr Matrix k_identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Matrix operator*(const Matrix& a, const Matrix& b) {
  Matrix out{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k) out[4 * c + r] += a[4 * k + r] * b[4 * c + k];
  return out;
}

Vec3d transform_point(const Matrix& m, Vec3d p) {
  return {m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12],
          m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
          m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]};
}

Vec3d transform_direction(const Matrix& m, Vec3d d) {
  return {m[0] * d.x + m[4] * d.y + m[8] * d.z, m[1] * d.x + m[5] * d.y + m[9] * d.z,
          m[2] * d.x + m[6] * d.y + m[10] * d.z};
}

bool all_finite(const std::vector<double>& values) {
  return std::ranges::all_of(values, [](double v) { return std::isfinite(v); });
}

// ---------------------------------------------------------------------------------------------
// Reading through tinygltf.

// tinygltf reads buffer files through these: a path is used as written (no expansion of ~ or
// $VARIABLES: a scene names files, never the shell's words), only regular files are read (not
// /dev/zero, not a pipe), and no more than the cap.
struct FileAccess {
  long long max_bytes;
};

bool file_exists(const std::string& path, void*) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}

std::string path_as_written(const std::string& path, void*) { return path; }

bool read_whole_file(std::vector<unsigned char>* out, std::string* error_text,
                     const std::string& path, void* user) {
  const long long max_bytes = static_cast<const FileAccess*>(user)->max_bytes;
  std::error_code error;
  const std::uintmax_t size = fs::file_size(path, error);
  if (error || !fs::is_regular_file(path, error)) {
    *error_text += path + ": not a readable file\n";
    return false;
  }
  if (size > static_cast<std::uintmax_t>(max_bytes)) {
    *error_text += path + ": larger than LoadLimits::max_file_bytes (" +
                   std::to_string(max_bytes) + " bytes)\n";
    return false;
  }
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    *error_text += path + ": cannot open\n";
    return false;
  }
  out->resize(size);
  const std::size_t got = size == 0 ? 0 : std::fread(out->data(), 1, size, file);
  std::fclose(file);
  if (got != size) {
    *error_text += path + ": read error\n";
    return false;
  }
  return true;
}

bool refuse_writing(std::string* error_text, const std::string&,
                    const std::vector<unsigned char>&, void*) {
  *error_text += "the glTF loader writes no files\n";
  return false;
}

// Images are not decoded by tinygltf: the bytes of a data URI are kept as they are, and an
// image in a buffer view is left where it is, to be read once its view is checked (tinygltf
// hands over a pointer into the buffer before any such check).
bool keep_image_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  if (image->bufferView >= 0) return true;
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

std::string first_line(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  constexpr std::size_t k_longest = 200; // a data URI can be megabytes long
  if (line.size() > k_longest) line = line.substr(0, k_longest) + "...";
  return line;
}

std::string read_scene_file(const std::string& path, long long max_bytes) {
  std::error_code error;
  if (!fs::exists(path, error)) throw InputError(path + ": no such file");
  if (fs::is_directory(path, error))
    throw InputError(path + ": is a directory, not a glTF file");
  std::vector<unsigned char> bytes;
  std::string error_text;
  FileAccess access{max_bytes};
  if (!read_whole_file(&bytes, &error_text, path, &access))
    throw InputError(first_line(error_text));
  if (bytes.empty()) throw InputError(path + ": the file is empty");
  return std::string(bytes.begin(), bytes.end());
}

tinygltf::Model parse_gltf(const std::string& path, const ch05::LoadLimits& load_limits) {
  const std::string bytes = read_scene_file(path, load_limits.max_file_bytes);
  tinygltf::TinyGLTF parser;
  FileAccess access{load_limits.max_file_bytes};
  parser.SetFsCallbacks(
      {&file_exists, &path_as_written, &read_whole_file, &refuse_writing, &access});
  parser.SetImageLoader(&keep_image_bytes, nullptr);
  tinygltf::Model model;
  std::string errors, warnings;
  std::string base_dir = fs::path(path).parent_path().string();
  if (base_dir.empty()) base_dir = ".";
  bool loaded = false;
  try {
    if (bytes.starts_with("glTF")) {
      loaded = parser.LoadBinaryFromMemory(&model, &errors, &warnings,
                                           reinterpret_cast<const unsigned char*>(bytes.data()),
                                           static_cast<unsigned int>(bytes.size()), base_dir);
    } else {
      loaded = parser.LoadASCIIFromString(&model, &errors, &warnings, bytes.data(),
                                          static_cast<unsigned int>(bytes.size()), base_dir);
    }
  } catch (const std::exception& error) { // e.g. an image data URI that decodes to nothing
    throw InputError(path + ": " + first_line(error.what()));
  }
  if (!loaded) {
    const std::string what = first_line(errors.empty() ? "tinygltf refused it" : errors);
    const bool json = what.find("json.exception") != std::string::npos ||
                      what.find("JSON") != std::string::npos;
    throw InputError(path + ": " + (json ? "malformed JSON: " : "") + what);
  }
  return model;
}

// ---------------------------------------------------------------------------------------------
// Accessors.

int component_bytes(int component_type) {
  switch (component_type) {
  case TINYGLTF_COMPONENT_TYPE_BYTE:
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
    return 1;
  case TINYGLTF_COMPONENT_TYPE_SHORT:
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
    return 2;
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
  case TINYGLTF_COMPONENT_TYPE_FLOAT:
    return 4;
  default:
    return 0;
  }
}

const char* component_name(int component_type) {
  switch (component_type) {
  case TINYGLTF_COMPONENT_TYPE_BYTE:
    return "byte";
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
    return "unsigned byte";
  case TINYGLTF_COMPONENT_TYPE_SHORT:
    return "short";
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
    return "unsigned short";
  case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    return "unsigned int";
  case TINYGLTF_COMPONENT_TYPE_FLOAT:
    return "float";
  default:
    return "unknown component type";
  }
}

const char* type_name(int type) {
  switch (type) {
  case TINYGLTF_TYPE_SCALAR:
    return "SCALAR";
  case TINYGLTF_TYPE_VEC2:
    return "VEC2";
  case TINYGLTF_TYPE_VEC3:
    return "VEC3";
  case TINYGLTF_TYPE_VEC4:
    return "VEC4";
  default:
    return "a matrix or unknown type";
  }
}

int type_components(int type) {
  switch (type) {
  case TINYGLTF_TYPE_SCALAR:
    return 1;
  case TINYGLTF_TYPE_VEC2:
    return 2;
  case TINYGLTF_TYPE_VEC3:
    return 3;
  case TINYGLTF_TYPE_VEC4:
    return 4;
  default:
    return 0;
  }
}

// Where an accessor's elements are: element i's bytes start at first + i * stride. An
// accessor without a buffer view is all zeros (glTF's rule); then first is null.
struct AccessorData {
  const unsigned char* first = nullptr;
  std::size_t stride = 0;
  std::size_t count = 0;
  int component_type = 0;
  bool normalized = false;

  template <class T> T component(std::size_t element, int k) const {
    T value{};
    if (first != nullptr)
      std::memcpy(&value, first + element * stride + k * sizeof(T), sizeof(T));
    return value;
  }
};

class GltfReader {
public:
  GltfReader(const std::string& path, const tinygltf::Model& model,
             const ch05::LoadLimits& load_limits)
      : path_(path), model_(model), limits_(load_limits) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_ + ": " + what);
  }

  // Accessor `index`, for `what` ("POSITION of mesh 0, primitive 1"), checked: its type and
  // component type among those allowed, its count within max_count, every byte it reads
  // inside its buffer view and the view inside its buffer.
  AccessorData accessor(int index, const std::string& what, int type,
                        std::initializer_list<int> component_types, long long max_count,
                        const char* limit_name) const {
    if (index < 0 || static_cast<std::size_t>(index) >= model_.accessors.size())
      fail(what + ": accessor " + std::to_string(index) + " does not exist (the file has " +
           std::to_string(model_.accessors.size()) + ")");
    const tinygltf::Accessor& a = model_.accessors[index];
    const std::string name = what + " (accessor " + std::to_string(index) + ")";
    if (a.type != type)
      fail(name + ": type " + type_name(a.type) + ", it must be " + type_name(type));
    if (std::ranges::find(component_types, a.componentType) == component_types.end())
      fail(name + ": component type " + component_name(a.componentType) +
           " is not one this attribute may have");
    if (a.sparse.isSparse) fail(name + ": sparse accessors are not read");
    if (a.count > static_cast<std::size_t>(max_count))
      fail(name + ": " + std::to_string(a.count) + " elements, more than LoadLimits::" +
           limit_name + " (" + std::to_string(max_count) + ")");
    AccessorData data;
    data.count = a.count;
    data.component_type = a.componentType;
    data.normalized = a.normalized;
    const std::size_t element = static_cast<std::size_t>(component_bytes(a.componentType)) *
                                static_cast<std::size_t>(type_components(type));
    data.stride = element;
    if (a.bufferView < 0) return data; // all zeros
    if (static_cast<std::size_t>(a.bufferView) >= model_.bufferViews.size())
      fail(name + ": buffer view " + std::to_string(a.bufferView) + " does not exist");
    const tinygltf::BufferView& view = model_.bufferViews[a.bufferView];
    const unsigned char* view_bytes = view_data(a.bufferView, name);
    if (view.byteStride != 0) {
      if (view.byteStride < element)
        fail(name + ": byte stride " + std::to_string(view.byteStride) +
             " is smaller than an element (" + std::to_string(element) + " bytes)");
      data.stride = view.byteStride;
    }
    // Every size here is at most the buffer's, and the count at most a limit below 2^31: the
    // products fit in 64 bits.
    const bool inside =
        a.count == 0 ||
        (a.byteOffset <= view.byteLength && data.stride <= view.byteLength &&
         a.byteOffset + (a.count - 1) * data.stride + element <= view.byteLength);
    if (!inside)
      fail(name + ": " + std::to_string(a.count) + " elements from byte " +
           std::to_string(a.byteOffset) + " run out of buffer view " +
           std::to_string(a.bufferView) + " (" + std::to_string(view.byteLength) + " bytes)");
    data.first = view_bytes + a.byteOffset;
    return data;
  }

  // The first byte of buffer view `index`, once the view is known to lie in its buffer.
  const unsigned char* view_data(int index, const std::string& name) const {
    const tinygltf::BufferView& view = model_.bufferViews[index];
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model_.buffers.size())
      fail(name + ": buffer view " + std::to_string(index) + " names buffer " +
           std::to_string(view.buffer) + ", which does not exist");
    const std::vector<unsigned char>& buffer = model_.buffers[view.buffer].data;
    if (view.byteLength > buffer.size() || view.byteOffset > buffer.size() - view.byteLength)
      fail(name + ": buffer view " + std::to_string(index) + " (bytes " +
           std::to_string(view.byteOffset) + " to " +
           std::to_string(view.byteOffset + view.byteLength) + ") runs out of buffer " +
           std::to_string(view.buffer) + " (" + std::to_string(buffer.size()) + " bytes)");
    return buffer.data() + view.byteOffset;
  }

  const std::string& path() const { return path_; }
  const tinygltf::Model& model() const { return model_; }
  const ch05::LoadLimits& limits() const { return limits_; }

private:
  const std::string& path_;
  const tinygltf::Model& model_;
  ch05::LoadLimits limits_;
};

// ---------------------------------------------------------------------------------------------
// The node graph.

// [listing:gltf_node_matrix]
// A node's own transform: its matrix, or translation * rotation * scale (glTF's order: scale
// first, then rotate, then translate), from the unit quaternion (x, y, z, w).
Matrix local_matrix(const tinygltf::Node& node, const GltfReader& reader, int index) {
  const std::string name = "node " + std::to_string(index);
  const auto check = [&](const std::vector<double>& values, std::size_t size,
                         const char* what) {
    if (!values.empty() && values.size() != size)
      reader.fail(name + ": " + what + " has " + std::to_string(values.size()) +
                  " numbers, not " + std::to_string(size));
    if (!all_finite(values))
      reader.fail(name + ": " + what + " holds a number that is not finite");
  };
  check(node.matrix, 16, "matrix");
  check(node.translation, 3, "translation");
  check(node.rotation, 4, "rotation");
  check(node.scale, 3, "scale");
  if (!node.matrix.empty()) {
    Matrix m{};
    std::copy(node.matrix.begin(), node.matrix.end(), m.begin());
    return m;
  }
  Matrix m = k_identity;
  if (!node.rotation.empty()) {
    double x = node.rotation[0], y = node.rotation[1], z = node.rotation[2],
           w = node.rotation[3];
    const double norm = std::sqrt(x * x + y * y + z * z + w * w);
    if (!(norm > 0.0)) reader.fail(name + ": rotation is the zero quaternion");
    x /= norm, y /= norm, z /= norm, w /= norm; // exporters round: made unit again
    m = {1 - 2 * (y * y + z * z),
         2 * (x * y + z * w),
         2 * (x * z - y * w),
         0,
         2 * (x * y - z * w),
         1 - 2 * (x * x + z * z),
         2 * (y * z + x * w),
         0,
         2 * (x * z + y * w),
         2 * (y * z - x * w),
         1 - 2 * (x * x + y * y),
         0,
         0,
         0,
         0,
         1};
  }
  if (!node.scale.empty())
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) m[4 * c + r] *= node.scale[c];
  if (!node.translation.empty())
    for (int r = 0; r < 3; ++r) m[12 + r] = node.translation[r];
  return m;
}
// [/listing:gltf_node_matrix]

// The nodes of the scene to draw, each with its world transform, parents before children.
struct PlacedNode {
  int node;
  Matrix world;
};

std::vector<int> root_nodes(const GltfReader& reader) {
  const tinygltf::Model& model = reader.model();
  if (model.defaultScene >= 0 &&
      static_cast<std::size_t>(model.defaultScene) >= model.scenes.size())
    reader.fail("the default scene " + std::to_string(model.defaultScene) + " does not exist");
  if (!model.scenes.empty())
    return model.scenes[static_cast<std::size_t>(std::max(model.defaultScene, 0))].nodes;
  // No scenes: every node that is no node's child.
  std::vector<bool> is_child(model.nodes.size(), false);
  for (const tinygltf::Node& node : model.nodes)
    for (int child : node.children)
      if (child >= 0 && static_cast<std::size_t>(child) < model.nodes.size())
        is_child[child] = true;
  std::vector<int> roots;
  for (std::size_t i = 0; i < model.nodes.size(); ++i)
    if (!is_child[i]) roots.push_back(static_cast<int>(i));
  return roots;
}

// [listing:gltf_flatten]
// The scene graph flattened: a walk from the roots that multiplies each node's transform onto
// its parent's. glTF's nodes form trees (a node has one parent at most, and a scene lists
// roots only), so a node reached twice is a broken file: a cycle, which would never end, or a
// node with two parents. A tree deeper than k_max_gltf_node_depth levels is refused too.
std::vector<PlacedNode> flatten_nodes(const GltfReader& reader) {
  const tinygltf::Model& model = reader.model();
  struct Pending {
    int node;
    Matrix parent_world;
    int depth; // a root is level 1
  };
  std::vector<PlacedNode> placed;
  std::vector<bool> reached(model.nodes.size(), false);
  std::vector<Pending> stack;
  const std::vector<int> roots = root_nodes(reader);
  for (auto root = roots.rbegin(); root != roots.rend(); ++root)
    stack.push_back({*root, k_identity, 1});
  while (!stack.empty()) {
    const Pending next = stack.back();
    stack.pop_back();
    const std::string name = "node " + std::to_string(next.node);
    if (next.node < 0 || static_cast<std::size_t>(next.node) >= model.nodes.size())
      reader.fail(name + " does not exist (the file has " + std::to_string(model.nodes.size()) +
                  ")");
    if (reached[next.node])
      reader.fail(name +
                  " is reached twice in the node graph (a cycle, or a node with two parents)");
    if (next.depth > k_max_gltf_node_depth)
      reader.fail(name + " is " + std::to_string(next.depth) +
                  " levels deep in the node graph, more than the " +
                  std::to_string(k_max_gltf_node_depth) + " this loader follows");
    reached[next.node] = true;
    const tinygltf::Node& node = model.nodes[next.node];
    const PlacedNode here{next.node, next.parent_world * local_matrix(node, reader, next.node)};
    placed.push_back(here);
    for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
      stack.push_back({*child, here.world, next.depth + 1});
  }
  return placed;
}
// [/listing:gltf_flatten]

// ---------------------------------------------------------------------------------------------
// Materials and their textures.

double number_in(const tinygltf::ExtensionMap& extensions, const std::string& extension,
                 const std::string& key, double fallback, const GltfReader& reader,
                 const std::string& where) {
  const auto found = extensions.find(extension);
  if (found == extensions.end() || !found->second.Has(key)) return fallback;
  const tinygltf::Value& value = found->second.Get(key);
  if (!value.IsNumber()) reader.fail(where + ": " + extension + "." + key + " is not a number");
  return value.GetNumberAsDouble();
}

class MaterialReader {
public:
  MaterialReader(const GltfReader& reader, MaterialScene& scene, const TextureLimits& limits)
      : reader_(reader), scene_(scene), limits_(limits), files_(scene, limits) {}

  Material material(int index) {
    const tinygltf::Material& g = reader_.model().materials[index];
    const std::string where =
        "material " + std::to_string(index) + (g.name.empty() ? "" : " '" + g.name + "'");
    const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4 || g.emissiveFactor.size() != 3)
      reader_.fail(where + ": baseColorFactor needs 4 numbers and emissiveFactor 3");
    const double strength = number_in(g.extensions, "KHR_materials_emissive_strength",
                                      "emissiveStrength", 1.0, reader_, where);
    const double ior = number_in(g.extensions, "KHR_materials_ior", "ior", 1.5, reader_, where);
    // KHR_materials_ior's 0 is no index at all: it asks for an infinite one, a Fresnel term
    // of 1 at every angle (the extension's specular-glossiness compatibility mode), which
    // metallic-roughness with an ior in [1, 4] cannot express.
    if (ior == 0.0)
      reader_.fail(where + ": KHR_materials_ior 0 (an infinite index, the specular-glossiness "
                           "compatibility mode) is not supported; the index must be in [1, 4]");
    Material m;
    m.model = MaterialModel::metallic_roughness;
    m.base_color = Vec3d{pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]}
                       .as<float>();
    m.metallic = static_cast<float>(pbr.metallicFactor);
    m.roughness = static_cast<float>(pbr.roughnessFactor);
    m.ior = static_cast<float>(ior);
    m.transmission = static_cast<float>(number_in(g.extensions, "KHR_materials_transmission",
                                                  "transmissionFactor", 0.0, reader_, where));
    if (!std::isfinite(strength) || strength < 0.0)
      reader_.fail(where + ": emissiveStrength " + std::to_string(strength) +
                   " is not a finite number >= 0");
    if (!all_finite(g.emissiveFactor)) reader_.fail(where + ": emissiveFactor is not finite");
    m.emission =
        (Vec3d{g.emissiveFactor[0], g.emissiveFactor[1], g.emissiveFactor[2]} * strength)
            .as<float>();
    m.base_color_texture = texture(pbr.baseColorTexture, true, where, "baseColorTexture");
    m.emission_texture = texture(g.emissiveTexture, true, where, "emissiveTexture");
    // One image holds both: roughness in G, metallic in B (the texture module reads them so).
    m.roughness_texture =
        texture(pbr.metallicRoughnessTexture, false, where, "metallicRoughnessTexture");
    m.metallic_texture = m.roughness_texture;
    if (const auto t = g.extensions.find("KHR_materials_transmission");
        t != g.extensions.end() && t->second.Has("transmissionTexture"))
      warn_once(reader_.path() + ": " + where +
                ": transmissionTexture is not read; transmissionFactor holds everywhere");
    check_material(m, reader_.path() + ": " + where);
    return m;
  }

private:
  void warn_once(const std::string& warning) {
    if (std::ranges::find(scene_.path.warnings, warning) == scene_.path.warnings.end())
      scene_.path.warnings.push_back(warning);
  }

  int texture(const tinygltf::TextureInfo& info, bool srgb, const std::string& where,
              const char* slot) {
    if (info.index < 0) return k_no_texture;
    const tinygltf::Model& model = reader_.model();
    const std::string name = where + ": " + slot;
    if (static_cast<std::size_t>(info.index) >= model.textures.size())
      reader_.fail(name + ": texture " + std::to_string(info.index) + " does not exist");
    if (info.texCoord != 0)
      warn_once(reader_.path() + ": " + name + " uses TEXCOORD_" +
                std::to_string(info.texCoord) + ", which is not read: TEXCOORD_0 is used");
    const int source = model.textures[info.index].source;
    if (source < 0) {
      warn_once(reader_.path() + ": " + name + ": texture " + std::to_string(info.index) +
                " has no image this loader reads; its material keeps its factor");
      return k_no_texture;
    }
    if (static_cast<std::size_t>(source) >= model.images.size())
      reader_.fail(name + ": image " + std::to_string(source) + " does not exist");
    const auto key = std::make_pair(source, srgb);
    if (const auto found = decoded_.find(key); found != decoded_.end()) return found->second;
    const tinygltf::Image& image = model.images[source];
    if (!image.uri.empty() && !image.as_is) // a file beside the glTF file
      return decoded_[key] = files_.index_of(image_path(image.uri), srgb, where);
    const std::string image_name = reader_.path() + ": image " + std::to_string(source);
    if (image.bufferView >= 0) {
      if (static_cast<std::size_t>(image.bufferView) >= model.bufferViews.size())
        reader_.fail("image " + std::to_string(source) + ": buffer view " +
                     std::to_string(image.bufferView) + " does not exist");
      const unsigned char* bytes =
          reader_.view_data(image.bufferView, "image " + std::to_string(source));
      return decoded_[key] = decode(bytes, model.bufferViews[image.bufferView].byteLength,
                                    image_name, srgb);
    }
    return decoded_[key] = decode(image.image.data(), image.image.size(), image_name, srgb);
  }

  // An image's URI as a path: relative to the glTF file, with %XX escapes decoded.
  std::string image_path(const std::string& uri) const {
    std::string decoded;
    for (std::size_t i = 0; i < uri.size(); ++i) {
      const auto hex = [](char c) {
        return c >= '0' && c <= '9'   ? c - '0'
               : c >= 'a' && c <= 'f' ? c - 'a' + 10
               : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                      : -1;
      };
      if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
        decoded += static_cast<char>(16 * hex(uri[i + 1]) + hex(uri[i + 2]));
        i += 2;
      } else {
        decoded += uri[i];
      }
    }
    return (fs::path(reader_.path()).parent_path() / decoded).string();
  }

  // [listing:gltf_embedded_image]
  // An image inside the glTF file (a data URI or a buffer view), decoded by stb_image: its
  // header is read first and its size checked against the limits, with what the scene's
  // other textures take, before a texel is decoded.
  int decode(const unsigned char* bytes, std::size_t size, const std::string& name, bool srgb) {
    if (size > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw InputError(name + ": an image of more than 2 GiB");
    int width = 0, height = 0, channels = 0;
    if (!stbi_info_from_memory(bytes, static_cast<int>(size), &width, &height, &channels))
      throw InputError(name + ": not an image stb_image can read (" + stbi_failure_reason() +
                       ")");
    check_texture_size(name, width, height, limits_, texture_bytes(scene_.textures));
    unsigned char* texels =
        stbi_load_from_memory(bytes, static_cast<int>(size), &width, &height, &channels, 4);
    if (texels == nullptr)
      throw InputError(name + ": corrupt image (" + stbi_failure_reason() + ")");
    std::vector<Rgba8> level0(static_cast<std::size_t>(width) *
                              static_cast<std::size_t>(height));
    std::memcpy(level0.data(), texels, level0.size() * 4);
    stbi_image_free(texels);
    scene_.textures.push_back(
        make_texture(name, width, height, std::move(level0), srgb, limits_));
    return static_cast<int>(scene_.textures.size()) - 1;
  }
  // [/listing:gltf_embedded_image]

  const GltfReader& reader_;
  MaterialScene& scene_;
  TextureLimits limits_;
  TextureFiles files_;
  std::map<std::pair<int, bool>, int> decoded_; // (image, sRGB) -> texture
};

// ---------------------------------------------------------------------------------------------
// Meshes.

// Triangles read from meshes: one mesh placed in the world per node (the flattened scene), or
// one mesh in its own space (the instanced scene).
struct Triangles {
  ch04::Mesh mesh;
  std::vector<int> material;            // per triangle, its material slot
  std::vector<std::array<Vec2f, 3>> uv; // per triangle, (0, 0) where a primitive has none
  bool has_uv = false;                  // whether any primitive gave TEXCOORD_0
};

// Checks a mesh index, naming where it came from.
void check_mesh_index(const GltfReader& reader, int mesh_index) {
  const std::size_t meshes = reader.model().meshes.size();
  if (mesh_index < 0 || static_cast<std::size_t>(mesh_index) >= meshes)
    reader.fail("mesh " + std::to_string(mesh_index) + " does not exist (the file has " +
                std::to_string(meshes) + ")");
}

// Reads meshes into Triangles, counting every vertex and triangle it reads against the
// limits, whichever Triangles they go to.
class MeshBuilder {
public:
  explicit MeshBuilder(const GltfReader& reader) : reader_(reader) {}

  // The triangles of mesh `mesh_index` appended to `out`, placed by `world`, or, where world
  // is null, as the file gives them; material slot `default_slot` for primitives that name
  // none.
  void add_mesh(int mesh_index, const Matrix* world, int default_slot, Triangles& out) {
    check_mesh_index(reader_, mesh_index);
    const tinygltf::Mesh& mesh = reader_.model().meshes[mesh_index];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p)
      add_primitive(mesh.primitives[p],
                    "mesh " + std::to_string(mesh_index) + ", primitive " + std::to_string(p),
                    world, default_slot, out);
  }

private:
  void add_primitive(const tinygltf::Primitive& primitive, const std::string& where,
                     const Matrix* world, int default_slot, Triangles& out) {
    const tinygltf::Model& model = reader_.model();
    const ch05::LoadLimits& limits = reader_.limits();
    // mode -1: tinygltf's "not given", which glTF defines as 4.
    if (primitive.mode != TINYGLTF_MODE_TRIANGLES && primitive.mode != -1)
      reader_.fail(where + ": mode " + std::to_string(primitive.mode) +
                   "; only triangles (mode 4) are read");
    if (primitive.material >= 0 &&
        static_cast<std::size_t>(primitive.material) >= model.materials.size())
      reader_.fail(where + ": material " + std::to_string(primitive.material) +
                   " does not exist (the file has " + std::to_string(model.materials.size()) +
                   ")");
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) reader_.fail(where + ": no POSITION");
    const long long vertices_left = limits.max_vertices - vertex_count_;
    const AccessorData positions =
        reader_.accessor(position->second, "POSITION of " + where, TINYGLTF_TYPE_VEC3,
                         {TINYGLTF_COMPONENT_TYPE_FLOAT}, vertices_left, "max_vertices");
    vertex_count_ += static_cast<long long>(positions.count);

    const int first_vertex = static_cast<int>(out.mesh.vertices.size());
    for (std::size_t i = 0; i < positions.count; ++i) {
      const Vec3d local{positions.component<float>(i, 0), positions.component<float>(i, 1),
                        positions.component<float>(i, 2)};
      if (!std::isfinite(local.x) || !std::isfinite(local.y) || !std::isfinite(local.z))
        reader_.fail("POSITION of " + where + ": vertex " + std::to_string(i) +
                     " is not finite");
      const Vec3d p = world != nullptr ? transform_point(*world, local) : local;
      if (!(max_component(elementwise_abs(p)) <= ch03::k_max_coordinate))
        reader_.fail(where + ": vertex " + std::to_string(i) +
                     " lies beyond the supported range (+-" +
                     std::to_string(ch03::k_max_coordinate) + ")" +
                     (world != nullptr ? " once placed by its nodes" : ""));
      out.mesh.vertices.push_back(p.as<float>());
    }

    std::vector<std::array<Vec2f, 3>> uv;
    const auto texcoord = primitive.attributes.find("TEXCOORD_0");
    AccessorData texcoords;
    if (texcoord != primitive.attributes.end()) {
      texcoords = reader_.accessor(
          texcoord->second, "TEXCOORD_0 of " + where, TINYGLTF_TYPE_VEC2,
          {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
           TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
          limits.max_vertices, "max_vertices");
      if (texcoords.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT && !texcoords.normalized)
        reader_.fail("TEXCOORD_0 of " + where +
                     ": integer texture coordinates must be "
                     "normalized");
      if (texcoords.count != positions.count)
        reader_.fail("TEXCOORD_0 of " + where + ": " + std::to_string(texcoords.count) +
                     " elements for " + std::to_string(positions.count) + " positions");
      out.has_uv = true;
    }
    const auto uv_of = [&](std::size_t vertex) -> Vec2f {
      if (texcoord == primitive.attributes.end()) return {};
      Vec2f t{};
      switch (texcoords.component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        t = {texcoords.component<std::uint8_t>(vertex, 0) / 255.0f,
             texcoords.component<std::uint8_t>(vertex, 1) / 255.0f};
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        t = {texcoords.component<std::uint16_t>(vertex, 0) / 65535.0f,
             texcoords.component<std::uint16_t>(vertex, 1) / 65535.0f};
        break;
      default:
        t = {texcoords.component<float>(vertex, 0), texcoords.component<float>(vertex, 1)};
      }
      if (!std::isfinite(t.x) || !std::isfinite(t.y))
        reader_.fail("TEXCOORD_0 of " + where + ": element " + std::to_string(vertex) +
                     " is not finite");
      return t;
    };

    // [listing:gltf_indices]
    // Three indices a triangle, or, without an index accessor, three vertices a triangle in
    // order. Each index is checked against this primitive's vertices.
    const long long triangles_left = limits.max_triangles - triangle_count_;
    std::vector<std::uint32_t> indices;
    if (primitive.indices >= 0) {
      const AccessorData index_data = reader_.accessor(
          primitive.indices, "indices of " + where, TINYGLTF_TYPE_SCALAR,
          {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
           TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
          3 * triangles_left, "max_triangles (three indices each)");
      indices.resize(index_data.count);
      for (std::size_t i = 0; i < index_data.count; ++i) {
        switch (index_data.component_type) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          indices[i] = index_data.component<std::uint8_t>(i, 0);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
          indices[i] = index_data.component<std::uint16_t>(i, 0);
          break;
        default:
          indices[i] = index_data.component<std::uint32_t>(i, 0);
        }
        if (indices[i] >= positions.count)
          reader_.fail("indices of " + where + ": index " + std::to_string(indices[i]) +
                       " (element " + std::to_string(i) + ") is out of range: there are " +
                       std::to_string(positions.count) + " vertices");
      }
    } else {
      if (static_cast<long long>(positions.count) > 3 * triangles_left)
        reader_.fail(where + ": " + std::to_string(positions.count / 3) +
                     " triangles, more than LoadLimits::max_triangles (" +
                     std::to_string(limits.max_triangles) + ")");
      indices.resize(positions.count);
      for (std::size_t i = 0; i < positions.count; ++i)
        indices[i] = static_cast<std::uint32_t>(i);
    }
    if (indices.size() % 3 != 0)
      reader_.fail(where + ": " + std::to_string(indices.size()) +
                   " corners, not a whole number of triangles");
    // [/listing:gltf_indices]

    const int slot = primitive.material >= 0 ? primitive.material : default_slot;
    for (std::size_t t = 0; t < indices.size(); t += 3) {
      out.mesh.triangles.push_back({first_vertex + static_cast<int>(indices[t]),
                                    first_vertex + static_cast<int>(indices[t + 1]),
                                    first_vertex + static_cast<int>(indices[t + 2])});
      out.material.push_back(slot);
      out.uv.push_back({uv_of(indices[t]), uv_of(indices[t + 1]), uv_of(indices[t + 2])});
    }
    triangle_count_ += static_cast<long long>(indices.size() / 3);
  }

  const GltfReader& reader_;
  long long vertex_count_ = 0;   // read so far, into any Triangles
  long long triangle_count_ = 0; // likewise
};

// [listing:gltf_camera]
// glTF's camera looks down its node's -z, with +y up, from the node's origin; yfov is the
// vertical field of view in radians.
std::optional<CameraSpec> camera_of(const GltfReader& reader,
                                    const std::vector<PlacedNode>& placed,
                                    std::vector<std::string>& warnings) {
  const tinygltf::Model& model = reader.model();
  if (model.cameras.empty()) return std::nullopt;
  const tinygltf::Node* node = nullptr;
  Matrix world = k_identity;
  for (const PlacedNode& p : placed)
    if (model.nodes[p.node].camera == 0) {
      node = &model.nodes[p.node];
      world = p.world;
      break;
    }
  if (node == nullptr) return std::nullopt; // not in the scene drawn
  const tinygltf::Camera& camera = model.cameras[0];
  if (camera.type != "perspective") {
    warnings.push_back(reader.path() + ": camera 0 is " + camera.type +
                       "; only a perspective camera is read");
    return std::nullopt;
  }
  const double yfov = camera.perspective.yfov;
  if (!(yfov > 0.0 && yfov < std::numbers::pi))
    reader.fail("camera 0: yfov " + std::to_string(yfov) + " is not in (0, pi)");
  const Vec3d eye = transform_point(world, {0.0, 0.0, 0.0});
  const Vec3d forward = transform_direction(world, {0.0, 0.0, -1.0});
  const Vec3d up = transform_direction(world, {0.0, 1.0, 0.0});
  if (!(length(forward) > 0.0 && length(up) > 0.0 && length(cross(forward, up)) > 0.0) ||
      !std::isfinite(length(forward) + length(up) + length(eye)))
    reader.fail("camera 0: its node's transform leaves no view direction and up");
  CameraSpec spec;
  spec.eye = eye;
  spec.target = eye + forward / length(forward);
  spec.up = up / length(up);
  spec.fov_degrees = yfov * 180.0 / std::numbers::pi;
  return spec;
}
// [/listing:gltf_camera]

// The extensions a file requires, each one this loader reads.
void check_required_extensions(const GltfReader& reader) {
  for (const std::string& extension : reader.model().extensionsRequired)
    if (!k_supported_required.contains(extension))
      reader.fail("requires the extension " + extension +
                  ", which this loader does not read (it reads "
                  "KHR_materials_emissive_strength, KHR_materials_ior and "
                  "KHR_materials_transmission)");
}

// Every material of the file, in its order (a primitive's material number is its slot), into
// scene.materials, their textures into scene.textures. Returns the slot glTF's default
// material takes if a primitive names none: the one after them.
int read_materials(const GltfReader& reader, MaterialScene& scene,
                   const TextureLimits& limits) {
  MaterialReader materials(reader, scene, limits);
  for (std::size_t k = 0; k < reader.model().materials.size(); ++k)
    scene.materials.push_back(materials.material(static_cast<int>(k)));
  return static_cast<int>(scene.materials.size());
}

// Zero-area triangles are valid and never hit, as in chapter 05; one with area must be large
// enough for float's products (chapter 03's supported range). Returns how many are flat;
// `where` begins each message ("" or "mesh 2: ").
long long count_flat_triangles(const GltfReader& reader, const ch04::Mesh& mesh,
                               const std::string& where) {
  long long flat = 0;
  for (int i = 0; i < static_cast<int>(mesh.triangles.size()); ++i) {
    const ch04::TriangleF t = mesh.triangle(i);
    if (ch04::is_flat(t)) {
      ++flat;
    } else if (const double span = ch04::triangle_span(t); span < ch03::k_min_length) {
      reader.fail(where + "triangle " + std::to_string(i) + " spans only " +
                  std::to_string(span) + "; a triangle with area must span at least " +
                  std::to_string(ch03::k_min_length));
    }
  }
  return flat;
}

void refuse_all_flat(const GltfReader& reader, long long flat, long long triangles) {
  if (flat == triangles)
    reader.fail("all " + std::to_string(flat) +
                " triangles are flat (zero area in float): nothing to intersect");
}

} // namespace

MaterialScene load_gltf_material_scene(const std::string& path, const TextureLimits& limits,
                                       const ch05::LoadLimits& load_limits) {
  const tinygltf::Model model = parse_gltf(path, load_limits);
  const GltfReader reader(path, model, load_limits);
  check_required_extensions(reader);

  MaterialScene scene;
  const int default_slot = read_materials(reader, scene, limits); // if a primitive needs it

  const std::vector<PlacedNode> placed = flatten_nodes(reader);
  MeshBuilder builder(reader);
  Triangles all;
  for (const PlacedNode& p : placed)
    if (model.nodes[p.node].mesh >= 0)
      builder.add_mesh(model.nodes[p.node].mesh, &p.world, default_slot, all);
  scene.path.mesh = std::move(all.mesh);
  scene.path.material = std::move(all.material);
  if (std::ranges::find(scene.path.material, default_slot) != scene.path.material.end())
    scene.materials.push_back(default_gltf_material());
  if (scene.path.mesh.triangles.empty())
    reader.fail("no triangles in the scene drawn (" + std::to_string(placed.size()) +
                " nodes)");
  if (all.has_uv) scene.uv = std::move(all.uv);
  scene.camera = camera_of(reader, placed, scene.path.warnings);

  const long long flat = count_flat_triangles(reader, scene.path.mesh, "");
  const auto triangles = static_cast<long long>(scene.path.mesh.triangles.size());
  refuse_all_flat(reader, flat, triangles);
  scene.path.description = path + ": " + std::to_string(triangles) + " triangles (" +
                           std::to_string(flat) + " of zero area, never hit), " +
                           std::to_string(model.materials.size()) + " materials, " +
                           std::to_string(scene.textures.size()) + " textures, " +
                           std::to_string(placed.size()) + " nodes";
  finish_material_scene(scene, path);
  return scene;
}

// The same walk of the nodes as the flattening loader's; where it appends a node's mesh placed
// by the node's world matrix, this reads the mesh once, the first time a node carries it, and
// appends an instance: the mesh's number and the matrix.
GltfInstancedScene load_gltf_instanced_scene(const std::string& path,
                                             const TextureLimits& limits,
                                             const ch05::LoadLimits& load_limits,
                                             long long max_instances) {
  const tinygltf::Model model = parse_gltf(path, load_limits);
  const GltfReader reader(path, model, load_limits);
  check_required_extensions(reader);

  // The materials and their textures, read as the flattening loader reads them.
  MaterialScene materials;
  const int default_slot = read_materials(reader, materials, limits);

  const std::vector<PlacedNode> placed = flatten_nodes(reader);
  GltfInstancedScene scene;
  MeshBuilder builder(reader);
  std::vector<int> kept(model.meshes.size(), -1); // glTF mesh -> its index in scene.meshes
  long long placed_triangles = 0;
  for (const PlacedNode& p : placed) {
    const int gltf_mesh = model.nodes[p.node].mesh;
    if (gltf_mesh < 0) continue;
    check_mesh_index(reader, gltf_mesh);
    if (static_cast<long long>(scene.instances.size()) >= max_instances)
      reader.fail("node " + std::to_string(p.node) + " places a mesh beyond the " +
                  std::to_string(max_instances) + " instances this loader keeps");
    if (kept[gltf_mesh] < 0) {
      Triangles read;
      builder.add_mesh(gltf_mesh, nullptr, default_slot, read);
      if (!read.has_uv) read.uv.clear();
      kept[gltf_mesh] = static_cast<int>(scene.meshes.size());
      scene.meshes.push_back(
          {std::move(read.mesh), std::move(read.material), std::move(read.uv), gltf_mesh});
    }
    scene.instances.push_back({kept[gltf_mesh], p.world, p.node});
    placed_triangles +=
        static_cast<long long>(scene.meshes[kept[gltf_mesh]].mesh.triangles.size());
  }
  const bool default_used = std::ranges::any_of(scene.meshes, [&](const GltfMesh& m) {
    return std::ranges::find(m.material, default_slot) != m.material.end();
  });
  if (default_used) materials.materials.push_back(default_gltf_material());
  if (placed_triangles == 0)
    reader.fail("no triangles in the scene drawn (" + std::to_string(placed.size()) +
                " nodes)");
  scene.camera = camera_of(reader, placed, materials.path.warnings);

  long long flat = 0, stored = 0;
  for (const GltfMesh& m : scene.meshes) {
    flat += count_flat_triangles(reader, m.mesh, "mesh " + std::to_string(m.gltf_mesh) + ": ");
    stored += static_cast<long long>(m.mesh.triangles.size());
  }
  refuse_all_flat(reader, flat, stored);
  scene.materials = std::move(materials.materials);
  scene.textures = std::move(materials.textures);
  scene.warnings = std::move(materials.path.warnings);
  scene.description = path + ": " + std::to_string(scene.meshes.size()) + " meshes of " +
                      std::to_string(stored) + " triangles (" + std::to_string(flat) +
                      " of zero area, never hit) placed by " +
                      std::to_string(scene.instances.size()) + " instances as " +
                      std::to_string(placed_triangles) + " triangles, " +
                      std::to_string(model.materials.size()) + " materials, " +
                      std::to_string(scene.textures.size()) + " textures, " +
                      std::to_string(placed.size()) + " nodes";
  return scene;
}

} // namespace rt::ch12
