// Chapter 12 tests of the scene loaders: the material room written as OBJ + MTL and as glTF
// loads to the same triangles, materials and texture coordinates; each MTL statement becomes
// the material field it names; glTF node transforms against positions worked out by hand; and
// every broken file refused in one line that names its problem.
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rt_catch.h"

#include "gltf_test_file.h"
#include "temp_folder.h"

#include "path_scene.h"
#include "rt/error.h"
#include "scene_loaders.h"

using namespace rt;
using namespace rt::ch12;
using nlohmann::json;
using rt::testing::contains;

using rt::testing::base64;
using rt::testing::bytes_of;
using rt::testing::GltfFile;
using rt::testing::one_triangle;
using rt::testing::TempFolder;

namespace {

const std::string k_assets = RT_ASSETS_DIR;

void require_near(Vec3f a, Vec3f b, float tolerance) {
  INFO("(" << a.x << ", " << a.y << ", " << a.z << ") against (" << b.x << ", " << b.y << ", "
           << b.z << ")");
  REQUIRE(std::abs(a.x - b.x) <= tolerance);
  REQUIRE(std::abs(a.y - b.y) <= tolerance);
  REQUIRE(std::abs(a.z - b.z) <= tolerance);
}

// The same material, field by field: the two files' decimals may round to floats an ulp apart.
void require_same_material(const Material& a, const Material& b) {
  REQUIRE(a.model == b.model);
  require_near(a.base_color, b.base_color, 1e-6f);
  require_near(a.emission, b.emission, 1e-5f);
  REQUIRE(a.metallic == Approx(b.metallic).margin(1e-6));
  REQUIRE(a.roughness == Approx(b.roughness).margin(1e-6));
  REQUIRE(a.ior == Approx(b.ior).margin(1e-6));
  REQUIRE(a.transmission == Approx(b.transmission).margin(1e-6));
  REQUIRE((a.base_color_texture == k_no_texture) == (b.base_color_texture == k_no_texture));
  REQUIRE((a.roughness_texture == k_no_texture) == (b.roughness_texture == k_no_texture));
  REQUIRE((a.metallic_texture == k_no_texture) == (b.metallic_texture == k_no_texture));
  REQUIRE((a.emission_texture == k_no_texture) == (b.emission_texture == k_no_texture));
}

const Material& material_of_triangle(const MaterialScene& scene, int i) {
  return scene.materials[scene.path.material[i]];
}

} // namespace

TEST_CASE("the material room's OBJ and glTF files load to the same scene", "[scenes]") {
  const MaterialScene obj = load_material_scene(k_assets + "/material_room.obj.gz");
  const MaterialScene gltf = load_material_scene(k_assets + "/material_room.gltf");
  CHECK(obj.path.warnings.empty());
  CHECK(gltf.path.warnings.empty());

  // 4 x 4 squares on each of 6 walls, the light quad, and 3 spheres of 2 * 64 * 31.
  const std::size_t triangles = 6 * 16 * 2 + 2 + 3 * 3968;
  REQUIRE(obj.path.mesh.triangles.size() == triangles);
  REQUIRE(gltf.path.mesh.triangles.size() == triangles);
  REQUIRE(obj.uv.size() == triangles);
  REQUIRE(gltf.uv.size() == triangles);
  for (int i = 0; i < static_cast<int>(triangles); ++i) {
    INFO("triangle " << i);
    const ch04::TriangleF a = obj.path.mesh.triangle(i), b = gltf.path.mesh.triangle(i);
    require_near(a.v0, b.v0, 1e-6f);
    require_near(a.v1, b.v1, 1e-6f);
    require_near(a.v2, b.v2, 1e-6f);
    require_same_material(material_of_triangle(obj, i), material_of_triangle(gltf, i));
    for (int c = 0; c < 3; ++c) {
      REQUIRE(obj.uv[i][c].x == Approx(gltf.uv[i][c].x).margin(1e-6));
      REQUIRE(obj.uv[i][c].y == Approx(gltf.uv[i][c].y).margin(1e-6));
    }
  }

  // The one texture, the checkerboard, is the same image, sRGB, in both.
  REQUIRE(obj.textures.size() == 1);
  REQUIRE(gltf.textures.size() == 1);
  REQUIRE(obj.textures[0].srgb);
  REQUIRE(gltf.textures[0].srgb);
  REQUIRE(obj.textures[0].width == gltf.textures[0].width);
  REQUIRE(obj.textures[0].texels.size() == gltf.textures[0].texels.size());
  REQUIRE(std::memcmp(obj.textures[0].texels.data(), gltf.textures[0].texels.data(),
                      obj.textures[0].texels.size() * sizeof(Rgba8)) == 0);

  // The materials as designed, found by what they are. Every triangle's material is glTF's
  // model; one material emits, the light's.
  for (const MaterialScene* scene : {&obj, &gltf}) {
    int glass = 0, rough_glass = 0, gold = 0, floor = 0, lights = 0;
    std::vector<bool> emitting(scene->materials.size(), false);
    for (int i = 0; i < static_cast<int>(triangles); ++i) {
      const Material& m = material_of_triangle(*scene, i);
      REQUIRE(m.model == MaterialModel::metallic_roughness);
      glass += m.transmission == 1.0f && m.roughness == 0.0f && m.ior == 1.5f;
      rough_glass += m.transmission == 1.0f && m.roughness == Approx(0.4f) && m.ior == 1.5f;
      gold += m.metallic == 1.0f && m.roughness == Approx(0.5f) &&
              m.base_color.y == Approx(0.766f) && m.base_color.z == Approx(0.336f);
      floor += m.base_color_texture != k_no_texture;
      if (m.emission.x > 0.0f) emitting[scene->path.material[i]] = true;
    }
    for (bool e : emitting) lights += e;
    CHECK(glass == 3968);
    CHECK(rough_glass == 3968);
    CHECK(gold == 3968);
    CHECK(floor == 32);
    CHECK(lights == 1);
    CHECK(scene->path.lights.triangles.size() == 2);
  }

  // The glTF's camera: at the front wall, looking down a little towards (0, 0.85, 0).
  REQUIRE_FALSE(obj.camera.has_value());
  REQUIRE(gltf.camera.has_value());
  const CameraSpec& camera = *gltf.camera;
  REQUIRE(camera.eye.x == Approx(0.0).margin(1e-9));
  REQUIRE(camera.eye.y == Approx(1.0));
  REQUIRE(camera.eye.z == Approx(0.98));
  const Vec3d view = camera.target - camera.eye;
  const Vec3d wanted = Vec3d{0.0, 0.85, 0.0} - camera.eye;
  REQUIRE(length(cross(view, wanted)) / (length(view) * length(wanted)) < 1e-9);
  REQUIRE(dot(view, wanted) > 0.0);
  REQUIRE(camera.fov_degrees == Approx(78.0));
}

TEST_CASE("MTL statements become the material fields they name", "[scenes]") {
  TempFolder folder("rt_ch12", "mtl");
  folder.copy(k_assets + "/material_room_floor.png", "checks.png");
  folder.copy(k_assets + "/material_room_floor.png", "grey.png");
  folder.write("m.mtl",
               "newmtl plain\nKd 0.5 0.25 0.125\n"
               "newmtl metal\nKd 0.9 0.8 0.7\nPm 1\nPr 0.3\n"
               "map_Pr grey.png\nmap_Pm grey.png\n"
               "newmtl glass\nKd 0.9 0.9 0.9\nillum 7\n"
               "newmtl tinted\nKd 0.9 0.9 0.9\nTf 0.5 0.6 0.7\nNi 1.33\n"
               "newmtl lamp\nKd 0 0 0\nKe 5 4 3\nmap_Ke checks.png\nmap_Kd checks.png\n"
               "newmtl bright\nKd 1 1 1\n");
  const std::string obj = folder.write(
      "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.1\nvt 1 0\nvt 0.5 1\n"
               "usemtl plain\nf 1/1 2/2 3/3\nusemtl metal\nf 1 2 3\nusemtl glass\nf 1 2 3\n"
               "usemtl tinted\nf 1 2 3\nusemtl lamp\nf 1/3 2/2 3/1\nusemtl bright\nf 1 2 3\n");

  SECTION("chapter 05 keeps the statements and whether the file gave them") {
    const ch05::ObjMesh mesh = ch05::load_obj(obj);
    REQUIRE(mesh.materials.size() == 6);
    const ch05::ObjMaterial &plain = mesh.materials[0], &metal = mesh.materials[1],
                            &glass = mesh.materials[2], &tinted = mesh.materials[3],
                            &lamp = mesh.materials[4];
    CHECK_FALSE((plain.has_metallic || plain.has_roughness || plain.has_ior ||
                 plain.has_illum || plain.has_transmittance || plain.has_dissolve));
    CHECK((metal.has_metallic && metal.has_roughness && !metal.has_ior));
    CHECK(metal.metallic == 1.0);
    CHECK(metal.roughness == Approx(0.3));
    CHECK(metal.roughness_texture == "grey.png");
    CHECK(metal.metallic_texture == "grey.png");
    CHECK((glass.has_illum && glass.illum == 7 && !glass.has_transmittance));
    CHECK((tinted.has_transmittance && tinted.has_ior));
    CHECK(tinted.transmittance.y == Approx(0.6));
    CHECK(tinted.ior == Approx(1.33));
    CHECK(lamp.emission_texture == "checks.png");
    CHECK(lamp.diffuse_texture == "checks.png");
    CHECK(plain.unreadable_pbr.empty());
  }

  SECTION("chapter 12's materials") {
    const MaterialScene scene = load_material_scene(obj);
    REQUIRE(scene.materials.size() == 7); // chapter 11's default in slot 0, then the file's
    const Material &plain = scene.materials[1], &metal = scene.materials[2],
                   &glass = scene.materials[3], &tinted = scene.materials[4],
                   &lamp = scene.materials[5], &bright = scene.materials[6];
    CHECK(scene.materials[0].model == MaterialModel::lambertian);
    CHECK(plain.model == MaterialModel::lambertian);
    require_near(plain.base_color, {0.5f, 0.25f, 0.125f}, 0.0f);
    CHECK(metal.model == MaterialModel::metallic_roughness);
    CHECK(metal.metallic == 1.0f);
    CHECK(metal.roughness == Approx(0.3f));
    CHECK(metal.ior == 1.5f); // glTF's default where the file gives no Ni
    CHECK(metal.transmission == 0.0f);
    REQUIRE(metal.roughness_texture != k_no_texture);
    REQUIRE(metal.metallic_texture == metal.roughness_texture); // one file, linear, once
    CHECK_FALSE(scene.textures[metal.roughness_texture].srgb);
    CHECK(glass.model == MaterialModel::metallic_roughness);
    CHECK(glass.transmission == 1.0f);
    CHECK(glass.roughness == 1.0f);
    CHECK(tinted.transmission == Approx(0.6f));
    CHECK(tinted.ior == Approx(1.33f));
    CHECK(lamp.model == MaterialModel::lambertian); // textures alone make no PBR material
    require_near(lamp.emission, {5.0f, 4.0f, 3.0f}, 0.0f);
    REQUIRE(lamp.emission_texture != k_no_texture);
    REQUIRE(lamp.base_color_texture == lamp.emission_texture); // both sRGB: one texture
    CHECK(scene.textures[lamp.emission_texture].srgb);
    CHECK(scene.textures.size() == 2);
    // Chapter 11's rule for Kd above 0.99, and its warning.
    require_near(bright.base_color, {0.99f, 0.99f, 0.99f}, 0.0f);
    REQUIRE(scene.path.warnings.size() == 1);
    CHECK_THAT(scene.path.warnings[0], contains("'bright'"));
    // path.materials as chapter 11's, for its light table.
    for (std::size_t k = 0; k < scene.materials.size(); ++k) {
      require_near(scene.path.materials[k].albedo, scene.materials[k].base_color, 0.0f);
      require_near(scene.path.materials[k].emission, scene.materials[k].emission, 0.0f);
    }
    // vt flipped (v' = 1 - v); faces without vt at (0, 0).
    REQUIRE(scene.uv.size() == 6);
    CHECK(scene.uv[0][0].x == 0.25f);
    CHECK(scene.uv[0][0].y == Approx(0.9f));
    CHECK(scene.uv[0][2].y == 0.0f);
    CHECK(scene.uv[4][0].y == 0.0f);
    CHECK(scene.uv[4][2].y == Approx(0.9f));
    CHECK(scene.uv[1][1].x == 0.0f);
    CHECK(scene.uv[1][1].y == 0.0f);
  }
}

TEST_CASE("the Cornell room's plain MTL loads to chapter 11's materials", "[scenes]") {
  const std::string room = k_assets + "/cornell_room.obj.gz";
  const ch11::PathScene chapter11 = ch11::load_path_scene(room);
  const MaterialScene scene = load_material_scene(room);
  REQUIRE(scene.path.mesh.triangles.size() == chapter11.mesh.triangles.size());
  REQUIRE(scene.path.material == chapter11.material);
  REQUIRE(scene.materials.size() == chapter11.materials.size());
  for (std::size_t k = 0; k < scene.materials.size(); ++k) {
    CHECK(scene.materials[k].model == MaterialModel::lambertian);
    require_near(scene.path.materials[k].albedo, chapter11.materials[k].albedo, 0.0f);
    require_near(scene.path.materials[k].emission, chapter11.materials[k].emission, 0.0f);
  }
  CHECK(scene.path.lights.triangles == chapter11.lights.triangles);
  CHECK(scene.uv.empty());
}

TEST_CASE("glTF node transforms are flattened through the scene graph", "[scenes]") {
  TempFolder folder("rt_ch12", "nodes");
  GltfFile file = one_triangle();
  // Node 0 moves by (10, 0, 0); its child, node 1, turns 90 degrees about z and scales by 2,
  // then draws the triangle; node 2, a root given by a matrix (scale 3, then move by
  // (0, 0, -4)), draws it too. A corner p of node 1's copy lands at (10, 0, 0) + Rz(90) 2 p,
  // with Rz(90) (x, y, z) = (-y, x, z).
  const double half = std::sin(std::numbers::pi / 4);
  file.doc["nodes"] = {
      {{"translation", {10, 0, 0}}, {"children", {1}}},
      {{"rotation", {0, 0, half, half}}, {"scale", {2, 2, 2}}, {"mesh", 0}},
      {{"matrix", {3, 0, 0, 0, 0, 3, 0, 0, 0, 0, 3, 0, 0, 0, -4, 1}}, {"mesh", 0}},
      {{"translation", {0, 0, 5}}, {"rotation", {0, half, 0, half}}, {"camera", 0}}};
  file.doc["scenes"] = {{{"nodes", {0, 2, 3}}}};
  file.doc["cameras"] = {
      {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};

  for (const std::string& path :
       {file.write(folder, "nodes"), file.write_embedded(folder, "embedded"),
        file.write_glb(folder, "binary")}) {
    INFO(path);
    const MaterialScene scene = load_material_scene(path);
    REQUIRE(scene.path.mesh.triangles.size() == 2);
    const ch04::TriangleF moved = scene.path.mesh.triangle(0);
    require_near(moved.v0, {10.0f, 0.0f, 0.0f}, 1e-5f);
    require_near(moved.v1, {10.0f, 2.0f, 0.0f}, 1e-5f); // (1, 0, 0) -> (0, 2, 0)
    require_near(moved.v2, {8.0f, 0.0f, 0.0f}, 1e-5f);  // (0, 1, 0) -> (-2, 0, 0)
    const ch04::TriangleF scaled = scene.path.mesh.triangle(1);
    require_near(scaled.v0, {0.0f, 0.0f, -4.0f}, 1e-6f);
    require_near(scaled.v1, {3.0f, 0.0f, -4.0f}, 1e-6f);
    require_near(scaled.v2, {0.0f, 3.0f, -4.0f}, 1e-6f);
    // No material named: glTF's default (white, metallic 1, roughness 1).
    REQUIRE(scene.materials.size() == 1);
    CHECK(scene.materials[0].model == MaterialModel::metallic_roughness);
    CHECK(scene.materials[0].metallic == 1.0f);
    CHECK(scene.uv.empty());
    // The camera turned 90 degrees about y looks down -x (its -z turned), from (0, 0, 5).
    REQUIRE(scene.camera.has_value());
    CHECK(scene.camera->eye.z == Approx(5.0));
    const Vec3d view = scene.camera->target - scene.camera->eye;
    CHECK(view.x == Approx(-1.0));
    CHECK(view.z == Approx(0.0).margin(1e-12));
    CHECK(scene.camera->up.y == Approx(1.0));
    CHECK(scene.camera->fov_degrees == Approx(0.5 * 180.0 / std::numbers::pi));
  }
}

TEST_CASE("glTF materials, their extensions and their textures", "[scenes]") {
  TempFolder folder("rt_ch12", "materials");
  folder.copy(k_assets + "/material_room_floor.png", "checks.png");
  GltfFile file = one_triangle();
  const int uv = file.add_accessor(
      bytes_of(std::vector<std::uint16_t>{0, 65535, 65535, 0, 0, 0}), 5123, 3, "VEC2");
  file.doc["accessors"][uv]["normalized"] = true;
  file.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv;
  file.doc["meshes"][0]["primitives"][0]["material"] = 0;
  file.doc["images"] = {{{"uri", "checks.png"}}};
  file.doc["textures"] = {{{"source", 0}}};
  file.doc["materials"] = {{{"pbrMetallicRoughness",
                             {{"baseColorFactor", {0.5, 0.6, 0.7, 1.0}},
                              {"metallicFactor", 0.25},
                              {"roughnessFactor", 0.75},
                              {"baseColorTexture", {{"index", 0}}},
                              {"metallicRoughnessTexture", {{"index", 0}}}}},
                            {"emissiveFactor", {1.0, 0.5, 0.0}},
                            {"extensions",
                             {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}},
                              {"KHR_materials_transmission", {{"transmissionFactor", 0.5}}},
                              {"KHR_materials_ior", {{"ior", 1.25}}}}}}};
  file.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_transmission",
                                "KHR_materials_ior"};
  file.doc["extensionsRequired"] = file.doc["extensionsUsed"];
  const MaterialScene scene = load_material_scene(file.write(folder, "materials"));
  REQUIRE(scene.materials.size() == 1);
  const Material& m = scene.materials[0];
  require_near(m.base_color, {0.5f, 0.6f, 0.7f}, 0.0f);
  CHECK(m.metallic == 0.25f);
  CHECK(m.roughness == 0.75f);
  CHECK(m.transmission == 0.5f);
  CHECK(m.ior == 1.25f);
  require_near(m.emission, {4.0f, 2.0f, 0.0f}, 0.0f);
  REQUIRE(scene.textures.size() == 2); // the image as colour (sRGB) and as data (linear)
  CHECK(scene.textures[m.base_color_texture].srgb);
  CHECK_FALSE(scene.textures[m.roughness_texture].srgb);
  CHECK(m.metallic_texture == m.roughness_texture);
  // Normalized unsigned shorts: 65535 is 1.
  REQUIRE(scene.uv.size() == 1);
  CHECK(scene.uv[0][0].x == 0.0f);
  CHECK(scene.uv[0][0].y == 1.0f);
  CHECK(scene.uv[0][1].x == 1.0f);
  CHECK(scene.uv[0][2].y == 0.0f);
  CHECK(scene.path.lights.triangles.size() == 1);
}

TEST_CASE("a missing texture file is one warning, a corrupt one an error", "[scenes]") {
  TempFolder folder("rt_ch12", "missing");
  folder.write("bad.png", std::string("\x89PNG\r\n\x1a\n this is not an image", 30));
  SECTION("OBJ") {
    folder.write("m.mtl", "newmtl a\nKd 0.5 0.5 0.5\nmap_Kd gone.png\nmap_Pr gone.png\n"
                          "newmtl b\nKd 0.25 0.5 0.5\nmap_Kd gone.png\n");
    const std::string obj = folder.write(
        "m.obj",
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\nusemtl b\nf 1 3 2\n");
    const MaterialScene scene = load_material_scene(obj);
    REQUIRE(scene.path.warnings.size() == 1);
    CHECK_THAT(scene.path.warnings[0], contains("gone.png"));
    CHECK(scene.materials[1].base_color_texture == k_no_texture);
    CHECK(scene.materials[1].base_color.x == 0.5f); // the factor kept
    folder.write("m.mtl", "newmtl a\nKd 0.5 0.5 0.5\nmap_Kd bad.png\n");
    REQUIRE_THROWS_AS(load_material_scene(obj), InputError);
  }
  SECTION("glTF") {
    GltfFile file = one_triangle();
    file.doc["meshes"][0]["primitives"][0]["material"] = 1;
    file.doc["images"] = {{{"uri", "gone.png"}}};
    file.doc["textures"] = {{{"source", 0}}};
    file.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}},
                             {{"pbrMetallicRoughness",
                               {{"baseColorTexture", {{"index", 0}}},
                                {"metallicRoughnessTexture", {{"index", 0}}}}}}};
    const MaterialScene scene = load_material_scene(file.write(folder, "missing"));
    REQUIRE(scene.path.warnings.size() == 1);
    CHECK_THAT(scene.path.warnings[0], contains("gone.png"));
    file.doc["images"] = {{{"uri", "bad.png"}}};
    REQUIRE_THROWS_AS(load_material_scene(file.write(folder, "corrupt")), InputError);
    file.doc["images"] = {
        {{"uri", "data:image/png;base64," + base64("\x89PNG\r\n\x1a\n not an image")}}};
    REQUIRE_THROWS_WITH(load_material_scene(file.write(folder, "embedded")),
                        contains("image 0"));
  }
}

TEST_CASE("MTL PBR statements that are not numbers are refused", "[scenes]") {
  TempFolder folder("rt_ch12", "unreadable");
  const std::string obj =
      folder.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n");
  for (const char* statement :
       {"Pm abc", "Pr 1e999", "Ni 1.5 2", "Tf 1 1", "illum 7.5", "Tf 2 0 0", "Pr 1.5"}) {
    INFO(statement);
    folder.write("m.mtl", std::string("newmtl a\nKd 0.5 0.5 0.5\n") + statement + "\n");
    REQUIRE_THROWS_WITH(load_material_scene(obj), contains("m.mtl: material 'a'"));
  }
}

TEST_CASE("broken glTF files are refused in one line naming the problem", "[scenes]") {
  TempFolder folder("rt_ch12", "refused");
  struct Case {
    const char* name;
    std::function<void(GltfFile&)> damage;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"required_draco",
       [](GltfFile& f) { f.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"}; },
       "requires the extension KHR_draco_mesh_compression"},
      {"accessor_past_view", [](GltfFile& f) { f.doc["accessors"][0]["count"] = 4; },
       "run out of buffer view"},
      {"accessor_offset_past_view",
       [](GltfFile& f) { f.doc["accessors"][0]["byteOffset"] = 8; }, "run out of buffer view"},
      {"view_past_buffer", [](GltfFile& f) { f.doc["bufferViews"][1]["byteOffset"] = 1000; },
       "runs out of buffer"},
      {"index_out_of_range",
       [](GltfFile& f) {
         f.doc["meshes"][0]["primitives"][0]["indices"] = f.add_indices({0, 1, 3});
       },
       "index 3 (element 2) is out of range"},
      {"position_vec2", [](GltfFile& f) { f.doc["accessors"][0]["type"] = "VEC2"; },
       "type VEC2, it must be VEC3"},
      {"position_shorts", [](GltfFile& f) { f.doc["accessors"][0]["componentType"] = 5123; },
       "component type unsigned short"},
      {"float_indices", [](GltfFile& f) { f.doc["accessors"][1]["componentType"] = 5126; },
       "component type float"},
      {"texcoord_not_normalized",
       [](GltfFile& f) {
         f.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = f.add_accessor(
             bytes_of(std::vector<std::uint8_t>{0, 0, 0, 0, 0, 0}), 5121, 3, "VEC2");
       },
       "must be normalized"},
      {"nan_position",
       [](GltfFile& f) {
         f.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] =
             f.add_positions({0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0, 0, 0, 1, 0});
       },
       "vertex 1 is not finite"},
      {"infinite_factor",
       [](GltfFile& f) {
         f.doc["materials"] = {{{"pbrMetallicRoughness", {{"roughnessFactor", 1e300}}}}};
         f.doc["meshes"][0]["primitives"][0]["material"] = 0;
       },
       "roughness inf"},
      {"strength_not_a_number",
       [](GltfFile& f) {
         f.doc["materials"] = {
             {{"extensions",
               {{"KHR_materials_emissive_strength", {{"emissiveStrength", "bright"}}}}}}};
       },
       "emissiveStrength is not a number"},
      {"number_overflow", // JSON's numbers are finite: one beyond a double is refused
       [](GltfFile& f) {
         f.doc["nodes"][0]["translation"] = {123456789, 0, 0};
         f.raw = {{"123456789", "-1e999"}};
       },
       "malformed JSON: [json.exception.out_of_range.406] number overflow"},
      {"infinite_emission",
       [](GltfFile& f) {
         f.doc["materials"] = {
             {{"emissiveFactor", {1, 1, 1}},
              {"extensions",
               {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1e300}}}}}}};
       },
       "material 0: emission inf is not in"},
      {"far_translation",
       [](GltfFile& f) {
         f.doc["nodes"][0]["translation"] = {1e300, 0, 0};
       },
       "vertex 0 lies beyond the supported range"},
      {"cycle",
       [](GltfFile& f) {
         f.doc["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}};
       },
       "node 0 is reached twice"},
      {"two_parents",
       [](GltfFile& f) {
         f.doc["nodes"] = {{{"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}};
         f.doc["scenes"][0]["nodes"] = {0, 1};
       },
       "node 2 is reached twice"},
      {"absurd_count", [](GltfFile& f) { f.doc["accessors"][1]["count"] = 40'000'000; },
       "more than LoadLimits::max_triangles"},
      {"lines", [](GltfFile& f) { f.doc["meshes"][0]["primitives"][0]["mode"] = 1; },
       "mode 1; only triangles (mode 4) are read"},
      {"missing_material",
       [](GltfFile& f) { f.doc["meshes"][0]["primitives"][0]["material"] = 7; },
       "material 7 does not exist"},
      {"missing_mesh", [](GltfFile& f) { f.doc["nodes"][0]["mesh"] = 3; },
       "mesh 3 does not exist"},
      {"missing_scene", [](GltfFile& f) { f.doc["scene"] = 2; },
       "default scene 2 does not exist"},
      {"ior_zero",
       [](GltfFile& f) {
         f.doc["materials"] = {{{"extensions", {{"KHR_materials_ior", {{"ior", 0}}}}}}};
       },
       "KHR_materials_ior 0"},
      {"ior_below_one",
       [](GltfFile& f) {
         f.doc["materials"] = {{{"extensions", {{"KHR_materials_ior", {{"ior", 0.5}}}}}}};
       },
       "index of refraction 0.5 is not in [1, 4]"},
      {"no_triangles", [](GltfFile& f) { f.doc["nodes"][0].erase("mesh"); }, "no triangles"},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    GltfFile file = one_triangle();
    c.damage(file);
    const std::string path = file.write(folder, c.name);
    REQUIRE_THROWS_AS(load_material_scene(path), InputError);
    REQUIRE_THROWS_WITH(load_material_scene(path),
                        contains(c.name + std::string(".gltf: ")) && contains(c.message));
  }

  SECTION("limits passed in") {
    GltfFile file = one_triangle();
    ch05::LoadLimits limits;
    limits.max_vertices = 2;
    REQUIRE_THROWS_WITH(load_gltf_material_scene(file.write(folder, "few"), {}, limits),
                        contains("more than LoadLimits::max_vertices (2)"));
  }
  SECTION("malformed JSON, missing buffer file, unknown file kind") {
    const std::string json_path = folder.write("broken.gltf", "{\"asset\": {\"version\": ");
    REQUIRE_THROWS_WITH(load_material_scene(json_path),
                        contains("broken.gltf: malformed JSON"));
    GltfFile file = one_triangle();
    const std::string path = file.write(folder, "lost");
    std::filesystem::remove(folder.path("lost.bin"));
    REQUIRE_THROWS_WITH(load_material_scene(path),
                        contains("lost.gltf: ") && contains("lost.bin"));
    REQUIRE_THROWS_AS(load_material_scene(folder.path("scene.ply")), UsageError);
    REQUIRE_THROWS_WITH(load_material_scene(folder.path("gone.glb")), contains("no such file"));
  }
  SECTION("zero-area triangles are kept and counted") {
    GltfFile file = one_triangle();
    file.doc["meshes"][0]["primitives"][0]["indices"] = file.add_indices({0, 1, 2, 0, 1, 1});
    const MaterialScene scene = load_material_scene(file.write(folder, "flat"));
    REQUIRE(scene.path.mesh.triangles.size() == 2);
    CHECK_THAT(scene.path.description, contains("1 of zero area"));
  }
}
