// Chapter 12 tests of the glTF loader that keeps the node graph (load_gltf_instanced_scene):
// every instance's mesh placed by its world matrix, in double and rounded to float as the
// flattening loader places it, and the instances concatenated in order, is the flattened
// scene bit for bit, on the material room, on a file of nested nodes and on the instanced
// shelf; both loaders refuse the same broken files with the same line; limits count what is
// stored, so a mesh placed 10 000 times loads where its flattened copy is refused.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "gltf_test_file.h"
#include "temp_folder.h"

#include "rt/error.h"
#include "scene_loaders.h"

using namespace rt;
using namespace rt::ch12;
using rt::testing::contains;

using rt::testing::bytes_of;
using rt::testing::GltfFile;
using rt::testing::one_triangle;
using rt::testing::TempFolder;

namespace {

const std::string k_assets = RT_ASSETS_DIR;

// p placed by a column-major 4 x 4 matrix, in double, rounded once to float: the flattening
// loader's arithmetic, written again here as the test's oracle.
Vec3f place(const std::array<double, 16>& m, Vec3f p) {
  const double x = p.x, y = p.y, z = p.z;
  return Vec3d{m[0] * x + m[4] * y + m[8] * z + m[12], m[1] * x + m[5] * y + m[9] * z + m[13],
               m[2] * x + m[6] * y + m[10] * z + m[14]}
      .as<float>();
}

bool same_bits(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b);
}

bool same_bits(Vec3f a, Vec3f b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

// The concatenation rule: instance k's vertex v is the flattened scene's vertex (vertices of
// instances 0 .. k-1) + v, placed, bit for bit; its triangle t the flattened scene's triangle
// (triangles of instances 0 .. k-1) + t, with the same corners, material slot and texture
// coordinates; the material table, the textures and the camera the same.
void require_flattens_to(const GltfInstancedScene& instanced, const MaterialScene& flat) {
  const ch04::Mesh& mesh = flat.path.mesh;
  std::size_t first_vertex = 0, first_triangle = 0;
  bool any_uv = false;
  for (std::size_t k = 0; k < instanced.instances.size(); ++k) {
    INFO("instance " << k);
    const GltfInstance& instance = instanced.instances[k];
    REQUIRE(instance.mesh >= 0);
    REQUIRE(instance.mesh < static_cast<int>(instanced.meshes.size()));
    const GltfMesh& kept = instanced.meshes[instance.mesh];
    REQUIRE(first_vertex + kept.mesh.vertices.size() <= mesh.vertices.size());
    REQUIRE(first_triangle + kept.mesh.triangles.size() <= mesh.triangles.size());
    for (std::size_t v = 0; v < kept.mesh.vertices.size(); ++v) {
      INFO("vertex " << v);
      REQUIRE(same_bits(place(instance.world, kept.mesh.vertices[v]),
                        mesh.vertices[first_vertex + v]));
    }
    REQUIRE(kept.material.size() == kept.mesh.triangles.size());
    REQUIRE((kept.uv.empty() || kept.uv.size() == kept.mesh.triangles.size()));
    any_uv = any_uv || !kept.uv.empty();
    for (std::size_t t = 0; t < kept.mesh.triangles.size(); ++t) {
      INFO("triangle " << t);
      const ch04::IndexedTriangle& a = kept.mesh.triangles[t];
      const ch04::IndexedTriangle& b = mesh.triangles[first_triangle + t];
      const int offset = static_cast<int>(first_vertex);
      REQUIRE(a.v0 + offset == b.v0);
      REQUIRE(a.v1 + offset == b.v1);
      REQUIRE(a.v2 + offset == b.v2);
      REQUIRE(kept.material[t] == flat.path.material[first_triangle + t]);
      if (!flat.uv.empty())
        for (int c = 0; c < 3; ++c) {
          const Vec2f expected = kept.uv.empty() ? Vec2f{} : kept.uv[t][c];
          REQUIRE(same_bits(expected.x, flat.uv[first_triangle + t][c].x));
          REQUIRE(same_bits(expected.y, flat.uv[first_triangle + t][c].y));
        }
    }
    first_vertex += kept.mesh.vertices.size();
    first_triangle += kept.mesh.triangles.size();
  }
  REQUIRE(first_vertex == mesh.vertices.size());
  REQUIRE(first_triangle == mesh.triangles.size());
  REQUIRE(any_uv == !flat.uv.empty());

  REQUIRE(instanced.materials.size() == flat.materials.size());
  for (std::size_t i = 0; i < flat.materials.size(); ++i) {
    INFO("material " << i);
    const Material &a = instanced.materials[i], &b = flat.materials[i];
    REQUIRE(a.model == b.model);
    REQUIRE(same_bits(a.base_color, b.base_color));
    REQUIRE(same_bits(a.emission, b.emission));
    REQUIRE(a.metallic == b.metallic);
    REQUIRE(a.roughness == b.roughness);
    REQUIRE(a.ior == b.ior);
    REQUIRE(a.transmission == b.transmission);
    REQUIRE(a.base_color_texture == b.base_color_texture);
    REQUIRE(a.roughness_texture == b.roughness_texture);
    REQUIRE(a.metallic_texture == b.metallic_texture);
    REQUIRE(a.emission_texture == b.emission_texture);
  }
  REQUIRE(instanced.textures.size() == flat.textures.size());
  REQUIRE(instanced.camera.has_value() == flat.camera.has_value());
  if (flat.camera) {
    REQUIRE(instanced.camera->eye == flat.camera->eye);
    REQUIRE(instanced.camera->target == flat.camera->target);
    REQUIRE(instanced.camera->up == flat.camera->up);
    REQUIRE(instanced.camera->fov_degrees == flat.camera->fov_degrees);
  }
}

// The line an InputError says, or "" where nothing is thrown.
std::string refusal(const std::function<void()>& load) {
  try {
    load();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// A file of nested nodes: mesh 0 (a tetrahedron's four faces, no material named), mesh 1 (a
// square of two triangles with material 0 and texture coordinates) and mesh 2, which no node
// of the scene carries. Node 0 (a root, moved and turned) holds node 1 (mesh 0, turned and
// scaled unevenly) and node 2 (given by a matrix), which holds node 3 (mesh 0 again, moved)
// and node 4 (mesh 1, scaled unevenly); node 5, another root, carries mesh 1 scaled by
// (0.5, 2, 3); node 6, in no scene, carries mesh 2.
GltfFile nested_nodes() {
  GltfFile file;
  const int tetrahedron = file.add_positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1});
  const int faces = file.add_indices({0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
  const int square = file.add_positions({-1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1});
  const int corners = file.add_indices({0, 2, 1, 0, 3, 2});
  const int uv =
      file.add_accessor(bytes_of(std::vector<float>{0, 0, 1, 0, 1, 1, 0, 1}), 5126, 4, "VEC2");
  const int other = file.add_positions({0, 0, 0, 2, 0, 0, 0, 2, 0});
  const int other_corners = file.add_indices({0, 1, 2});
  file.doc["meshes"] = {
      {{"primitives", {{{"attributes", {{"POSITION", tetrahedron}}}, {"indices", faces}}}}},
      {{"primitives",
        {{{"attributes", {{"POSITION", square}, {"TEXCOORD_0", uv}}},
          {"indices", corners},
          {"material", 0}}}}},
      {{"primitives", {{{"attributes", {{"POSITION", other}}}, {"indices", other_corners}}}}}};
  file.doc["materials"] = {
      {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.3, 0.2, 1.0}}}}}};
  const double c = std::cos(0.3), s = std::sin(0.3);
  file.doc["nodes"] = {
      {{"translation", {1.5, -2, 7.25}},
       {"rotation", {0, std::sin(0.35), 0, std::cos(0.35)}},
       {"children", {1, 2}}},
      {{"rotation", {0.2, 0.4, 0.1, 0.8}}, {"scale", {2, 0.5, 3}}, {"mesh", 0}},
      {{"matrix", {c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, 3, 1, -2, 1}}, {"children", {3, 4}}},
      {{"translation", {0.125, 10, -3}}, {"mesh", 0}},
      {{"scale", {0.25, 1, 4}}, {"mesh", 1}},
      {{"scale", {0.5, 2, 3}}, {"translation", {-4, 0, 0}}, {"mesh", 1}},
      {{"mesh", 2}}};
  file.doc["scenes"] = {{{"nodes", {0, 5}}}};
  file.doc["scene"] = 0;
  return file;
}

// A chain of `levels` nodes, each the child of the one before, the last carrying mesh 0.
GltfFile chain(int levels) {
  GltfFile file = one_triangle();
  file.doc["nodes"] = nlohmann::json::array();
  for (int i = 0; i < levels; ++i) {
    nlohmann::json node = {{"translation", {0.5, 0, 0}}};
    if (i + 1 < levels)
      node["children"] = {i + 1};
    else
      node["mesh"] = 0;
    file.doc["nodes"].push_back(node);
  }
  return file;
}

} // namespace

TEST_CASE("the material room's instances concatenate to its flattened scene",
          "[gltf-instances]") {
  const std::string room = k_assets + "/material_room.gltf";
  const GltfInstancedScene instanced = load_gltf_instanced_scene(room);
  const MaterialScene flat = load_gltf_material_scene(room);
  CHECK(instanced.warnings.empty());
  REQUIRE(!instanced.instances.empty());
  require_flattens_to(instanced, flat);
  CHECK_THAT(instanced.description, contains("material_room.gltf: "));
}

TEST_CASE("the instanced shelf's instances concatenate to its flattened scene",
          "[gltf-instances]") {
  // tools/make-instanced-scene.py: 5 meshes of 1 360 triangles placed by 35 instances as
  // 12 280 triangles, 46 nodes, four levels deep.
  const std::string shelf = k_assets + "/instanced_shelf.gltf";
  const GltfInstancedScene instanced = load_gltf_instanced_scene(shelf);
  const MaterialScene flat = load_gltf_material_scene(shelf);
  CHECK(instanced.warnings.empty());
  REQUIRE(instanced.meshes.size() == 5);
  REQUIRE(instanced.instances.size() == 35);
  std::size_t stored = 0;
  for (const GltfMesh& m : instanced.meshes) stored += m.mesh.triangles.size();
  CHECK(stored == 1360);
  REQUIRE(flat.path.mesh.triangles.size() == 12280);
  CHECK_THAT(instanced.description, contains("5 meshes of 1360 triangles") &&
                                        contains("35 instances as 12280 triangles") &&
                                        contains("46 nodes"));
  REQUIRE(instanced.camera.has_value());
  require_flattens_to(instanced, flat);
}

TEST_CASE("nested nodes: instances in the walk's order, meshes read once", "[gltf-instances]") {
  TempFolder folder("rt_ch12", "instances");
  GltfFile file = nested_nodes();
  for (const std::string& path :
       {file.write(folder, "nested"), file.write_embedded(folder, "embedded"),
        file.write_glb(folder, "binary")}) {
    INFO(path);
    const GltfInstancedScene instanced = load_gltf_instanced_scene(path);
    const MaterialScene flat = load_gltf_material_scene(path);
    // Depth first, children in order: nodes 1, 3, 4 under root 0, then root 5. Mesh 0 is met
    // first (node 1), then mesh 1 (node 4); mesh 2 (node 6, in no scene) is left out.
    REQUIRE(instanced.instances.size() == 4);
    const std::array<int, 4> nodes = {1, 3, 4, 5}, meshes = {0, 0, 1, 1};
    for (int k = 0; k < 4; ++k) {
      CHECK(instanced.instances[k].node == nodes[k]);
      CHECK(instanced.instances[k].mesh == meshes[k]);
    }
    REQUIRE(instanced.meshes.size() == 2);
    CHECK(instanced.meshes[0].gltf_mesh == 0);
    CHECK(instanced.meshes[1].gltf_mesh == 1);
    CHECK(instanced.meshes[0].mesh.triangles.size() == 4);
    CHECK(instanced.meshes[1].mesh.triangles.size() == 2);
    // Object space: the file's floats as they are, the uv only where the mesh has them.
    CHECK(instanced.meshes[0].mesh.vertices[3] == Vec3f{0.0f, 0.0f, 1.0f});
    CHECK(instanced.meshes[0].uv.empty());
    REQUIRE(instanced.meshes[1].uv.size() == 2);
    // The tetrahedron names no material: glTF's default, in the slot after the file's one.
    CHECK(instanced.meshes[0].material == std::vector<int>{1, 1, 1, 1});
    CHECK(instanced.meshes[1].material == std::vector<int>{0, 0});
    // Node 5's world matrix is its own: scale (0.5, 2, 3), then move by (-4, 0, 0).
    const std::array<double, 16> node5 = {0.5, 0, 0, 0, 0, 2, 0, 0, 0, 0, 3, 0, -4, 0, 0, 1};
    CHECK(instanced.instances[3].world == node5);
    // 12 triangles placed from 6 stored.
    CHECK_THAT(instanced.description,
               contains("2 meshes of 6 triangles") && contains("4 instances as 12 triangles"));
    require_flattens_to(instanced, flat);
  }
}

TEST_CASE("a node graph deeper than the bound is refused by both glTF loaders",
          "[gltf-instances]") {
  TempFolder folder("rt_ch12", "depth");
  GltfFile deepest = chain(k_max_gltf_node_depth);
  const std::string fits = deepest.write(folder, "deepest");
  const GltfInstancedScene instanced = load_gltf_instanced_scene(fits);
  REQUIRE(instanced.instances.size() == 1);
  CHECK(instanced.instances[0].node == k_max_gltf_node_depth - 1);
  CHECK(instanced.instances[0].world[12] == 0.5 * k_max_gltf_node_depth);
  require_flattens_to(instanced, load_gltf_material_scene(fits));

  GltfFile deeper = chain(k_max_gltf_node_depth + 1);
  const std::string path = deeper.write(folder, "deeper");
  const std::string expected = path + ": node " + std::to_string(k_max_gltf_node_depth) +
                               " is " + std::to_string(k_max_gltf_node_depth + 1) +
                               " levels deep in the node graph, more than the " +
                               std::to_string(k_max_gltf_node_depth) + " this loader follows";
  CHECK(refusal([&] { load_gltf_instanced_scene(path); }) == expected);
  CHECK(refusal([&] { load_gltf_material_scene(path); }) == expected);
}

TEST_CASE("broken glTF files are refused by the instanced loader as by the flattening one",
          "[gltf-instances]") {
  TempFolder folder("rt_ch12", "instances_refused");
  struct Case {
    const char* name;
    std::function<void(GltfFile&)> damage;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"cycle",
       [](GltfFile& f) {
         f.doc["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}};
       },
       "node 0 is reached twice in the node graph (a cycle, or a node with two parents)"},
      {"two_parents",
       [](GltfFile& f) {
         f.doc["nodes"] = {{{"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}};
         f.doc["scenes"][0]["nodes"] = {0, 1};
       },
       "node 2 is reached twice in the node graph"},
      {"required_draco",
       [](GltfFile& f) { f.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"}; },
       "requires the extension KHR_draco_mesh_compression"},
      {"accessor_past_view", [](GltfFile& f) { f.doc["accessors"][0]["count"] = 4; },
       "run out of buffer view"},
      {"view_past_buffer", [](GltfFile& f) { f.doc["bufferViews"][1]["byteOffset"] = 1000; },
       "runs out of buffer"},
      {"index_out_of_range",
       [](GltfFile& f) {
         f.doc["meshes"][0]["primitives"][0]["indices"] = f.add_indices({0, 1, 3});
       },
       "index 3 (element 2) is out of range"},
      {"position_vec2", [](GltfFile& f) { f.doc["accessors"][0]["type"] = "VEC2"; },
       "type VEC2, it must be VEC3"},
      {"nan_position",
       [](GltfFile& f) {
         f.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] =
             f.add_positions({0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0, 0, 0, 1, 0});
       },
       "vertex 1 is not finite"},
      {"far_vertex",
       [](GltfFile& f) {
         f.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] =
             f.add_positions({0, 0, 0, 1e11f, 0, 0, 0, 1, 0});
       },
       "vertex 1 lies beyond the supported range"},
      {"number_overflow",
       [](GltfFile& f) {
         f.doc["nodes"][0]["translation"] = {123456789, 0, 0};
         f.raw = {{"123456789", "-1e999"}};
       },
       "malformed JSON"},
      {"infinite_factor",
       [](GltfFile& f) {
         f.doc["materials"] = {{{"pbrMetallicRoughness", {{"roughnessFactor", 1e300}}}}};
         f.doc["meshes"][0]["primitives"][0]["material"] = 0;
       },
       "roughness inf"},
      {"zero_quaternion",
       [](GltfFile& f) {
         f.doc["nodes"][0]["rotation"] = {0, 0, 0, 0};
       },
       "node 0: rotation is the zero quaternion"},
      {"missing_node",
       [](GltfFile& f) {
         f.doc["scenes"][0]["nodes"] = {0, 4};
       },
       "node 4 does not exist"},
      {"missing_mesh", [](GltfFile& f) { f.doc["nodes"][0]["mesh"] = 3; },
       "mesh 3 does not exist"},
      {"missing_material",
       [](GltfFile& f) { f.doc["meshes"][0]["primitives"][0]["material"] = 7; },
       "material 7 does not exist"},
      {"absurd_count", [](GltfFile& f) { f.doc["accessors"][1]["count"] = 40'000'000; },
       "more than LoadLimits::max_triangles"},
      {"lines", [](GltfFile& f) { f.doc["meshes"][0]["primitives"][0]["mode"] = 1; },
       "mode 1; only triangles (mode 4) are read"},
      {"tiny_triangle",
       [](GltfFile& f) {
         f.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] =
             f.add_positions({0, 0, 0, 1e-12f, 0, 0, 0, 1e-12f, 0});
       },
       "triangle 0 spans only"},
      {"all_flat",
       [](GltfFile& f) {
         f.doc["meshes"][0]["primitives"][0]["indices"] = f.add_indices({0, 1, 1});
       },
       "all 1 triangles are flat"},
      {"no_triangles", [](GltfFile& f) { f.doc["nodes"][0].erase("mesh"); }, "no triangles"},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    GltfFile file = one_triangle();
    c.damage(file);
    const std::string path = file.write(folder, c.name);
    const std::string instanced = refusal([&] { load_gltf_instanced_scene(path); });
    CHECK_THAT(instanced, contains(path + ": ") && contains(c.message));
    CHECK(instanced.find('\n') == std::string::npos);
    const std::string flat = refusal([&] { load_gltf_material_scene(path); });
    CHECK_THAT(flat, contains(path + ": ") && contains(c.message));
  }

  SECTION("malformed JSON and a missing buffer file") {
    const std::string broken = folder.write("broken.gltf", "{\"asset\": {\"version\": ");
    CHECK_THAT(refusal([&] { load_gltf_instanced_scene(broken); }),
               contains("broken.gltf: malformed JSON"));
    GltfFile file = one_triangle();
    const std::string path = file.write(folder, "lost");
    std::filesystem::remove(folder.path("lost.bin"));
    CHECK_THAT(refusal([&] { load_gltf_instanced_scene(path); }),
               contains("lost.gltf: ") && contains("lost.bin"));
  }
}

TEST_CASE("the instanced loader's limits count the triangles stored, not those placed",
          "[gltf-instances]") {
  TempFolder folder("rt_ch12", "instances_limits");
  // A square of two triangles placed by 10 000 nodes, 100 x 100 on a grid: 20 000 triangles
  // flattened, 2 stored.
  GltfFile file = one_triangle();
  file.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] =
      file.add_positions({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  file.doc["meshes"][0]["primitives"][0]["indices"] = file.add_indices({0, 1, 2, 0, 2, 3});
  constexpr int k_side = 100;
  file.doc["nodes"] = nlohmann::json::array();
  file.doc["scenes"][0]["nodes"] = nlohmann::json::array();
  for (int i = 0; i < k_side * k_side; ++i) {
    file.doc["nodes"].push_back(
        {{"translation", {2 * (i % k_side), 2 * (i / k_side), 0}}, {"mesh", 0}});
    file.doc["scenes"][0]["nodes"].push_back(i);
  }
  const std::string path = file.write(folder, "grid");
  ch05::LoadLimits limits;
  limits.max_triangles = 1000;
  limits.max_vertices = 1000;

  const GltfInstancedScene instanced = load_gltf_instanced_scene(path, {}, limits);
  REQUIRE(instanced.meshes.size() == 1);
  REQUIRE(instanced.meshes[0].mesh.triangles.size() == 2);
  REQUIRE(instanced.instances.size() == k_side * k_side);
  const GltfInstance& last = instanced.instances.back();
  CHECK(last.node == k_side * k_side - 1);
  CHECK(last.world[12] == 2.0 * (k_side - 1));
  CHECK(last.world[13] == 2.0 * (k_side - 1));
  CHECK_THAT(instanced.description, contains("10000 instances as 20000 triangles"));
  CHECK_THAT(refusal([&] { load_gltf_material_scene(path, {}, limits); }),
             contains("grid.gltf: ") && contains("more than LoadLimits::max_"));

  SECTION("more instances than the bound") {
    const std::string expected =
        path + ": node 9999 places a mesh beyond the 9999 instances this loader keeps";
    CHECK(refusal([&] { load_gltf_instanced_scene(path, {}, limits, 9999); }) == expected);
    CHECK(load_gltf_instanced_scene(path, {}, limits, 10000).instances.size() == 10000);
  }
}
