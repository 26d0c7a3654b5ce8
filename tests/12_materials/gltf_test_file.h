// Chapter 12's tests write small glTF files of their own: JSON made with nlohmann's library and
// one buffer of raw bytes, written beside it as a .bin file, as a base64 data URI, or packed
// with it into a .glb. The scene tests and the instance tests both build their files with
// these.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "temp_folder.h"

namespace rt::testing {

inline std::string base64(const std::string& bytes) {
  static const char* k_digits =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t n = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) n |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) n |= static_cast<std::uint8_t>(bytes[i + 2]);
    out += k_digits[(n >> 18) & 63];
    out += k_digits[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? k_digits[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? k_digits[n & 63] : '=';
  }
  return out;
}

template <class T> std::string bytes_of(const std::vector<T>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

// A glTF file made in a test: the JSON and one buffer, written beside it as a .bin file, as
// a data URI, or packed with it into a .glb.
struct GltfFile {
  nlohmann::json doc;
  std::string bin;
  // Text put in place of a number after the JSON is written: JSON has no infinity, but a
  // number too large for a double ("1e999") reads as one.
  std::vector<std::pair<std::string, std::string>> raw;

  std::string text() const {
    std::string out = doc.dump();
    for (const auto& [from, to] : raw)
      for (std::size_t at; (at = out.find(from)) != std::string::npos;)
        out.replace(at, from.size(), to);
    return out;
  }

  GltfFile() {
    doc = {{"asset", {{"version", "2.0"}}},
           {"accessors", nlohmann::json::array()},
           {"bufferViews", nlohmann::json::array()}};
  }

  // The bytes as a new buffer view and an accessor over all of them.
  int add_accessor(const std::string& bytes, int component_type, int count,
                   const std::string& type) {
    while (bin.size() % 4 != 0) bin += '\0';
    doc["bufferViews"].push_back(
        {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}});
    bin += bytes;
    doc["accessors"].push_back({{"bufferView", doc["bufferViews"].size() - 1},
                                {"componentType", component_type},
                                {"count", count},
                                {"type", type}});
    return static_cast<int>(doc["accessors"].size()) - 1;
  }
  int add_positions(const std::vector<float>& xyz) {
    return add_accessor(bytes_of(xyz), 5126, static_cast<int>(xyz.size() / 3), "VEC3");
  }
  int add_indices(const std::vector<std::uint16_t>& indices) {
    return add_accessor(bytes_of(indices), 5123, static_cast<int>(indices.size()), "SCALAR");
  }

  std::string write(const TempFolder& folder, const std::string& name) {
    doc["buffers"] = {{{"byteLength", bin.size()}, {"uri", name + ".bin"}}};
    folder.write(name + ".bin", bin);
    return folder.write(name + ".gltf", text());
  }
  std::string write_embedded(const TempFolder& folder, const std::string& name) {
    doc["buffers"] = {{{"byteLength", bin.size()},
                       {"uri", "data:application/octet-stream;base64," + base64(bin)}}};
    return folder.write(name + ".gltf", text());
  }
  std::string write_glb(const TempFolder& folder, const std::string& name) {
    doc["buffers"] = {{{"byteLength", bin.size()}}};
    std::string json_text = text();
    while (json_text.size() % 4 != 0) json_text += ' ';
    std::string body = bin;
    while (body.size() % 4 != 0) body += '\0';
    const auto word = [](std::uint32_t v) {
      return std::string(reinterpret_cast<char*>(&v), 4);
    };
    const std::uint32_t total = 12 + 8 + static_cast<std::uint32_t>(json_text.size()) + 8 +
                                static_cast<std::uint32_t>(body.size());
    const std::string glb = "glTF" + word(2) + word(total) +
                            word(static_cast<std::uint32_t>(json_text.size())) + "JSON" +
                            json_text + word(static_cast<std::uint32_t>(body.size())) + "BIN" +
                            std::string(1, '\0') + body;
    return folder.write(name + ".glb", glb);
  }
};

// One triangle (0,0,0), (1,0,0), (0,1,0) as mesh 0 of a file with a node that draws it.
inline GltfFile one_triangle() {
  GltfFile file;
  const int positions = file.add_positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const int indices = file.add_indices({0, 1, 2});
  file.doc["meshes"] = {
      {{"primitives", {{{"attributes", {{"POSITION", positions}}}, {"indices", indices}}}}}};
  file.doc["nodes"] = {{{"mesh", 0}}};
  file.doc["scenes"] = {{{"nodes", {0}}}};
  file.doc["scene"] = 0;
  return file;
}

} // namespace rt::testing
