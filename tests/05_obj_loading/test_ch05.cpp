// Chapter 05 tests: exact meshes from small OBJ files (fans, relative indices, objects,
// materials, normals and texture coordinates), two classic loader mistakes, an icosphere
// written out and read back bit for bit, gzip, the load limits, the file system, long lines.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>
#include <zlib.h>

#include "rt_catch.h"

#include "temp_folder.h"

#include "mesh_gen.h"
#include "mesh_invariants.h"
#include "obj_loader.h"
#include "rt/error.h"

using namespace rt;
using namespace rt::ch05;
using Triangles = std::vector<std::array<int, 3>>;

using rt::testing::TempFolder;

namespace {

std::string corpus_path(const std::string& file) {
  return std::string(RT_CH05_CORPUS_DIR) + "/" + file;
}

// Index triples as arrays, which Catch prints when a comparison fails.
Triangles as_arrays(const std::vector<ch04::IndexedTriangle>& triangles) {
  Triangles out;
  for (const ch04::IndexedTriangle& t : triangles) out.push_back({t.v0, t.v1, t.v2});
  return out;
}

ObjMesh parse(const std::string& text, const LoadLimits& limits = {}) {
  return parse_obj(text, "test.obj", limits);
}

template <class Load> std::string error_of(Load&& load) {
  try {
    load();
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no error)";
}

std::string parse_error(const std::string& text, const LoadLimits& limits = {}) {
  return error_of([&] { parse(text, limits); });
}

// One gzip member holding `text`, made with zlib.
std::string gzip(const std::string& text) {
  z_stream z{};
  REQUIRE(deflateInit2(&z, 9, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY) == Z_OK);
  std::string packed(deflateBound(&z, static_cast<uLong>(text.size())), '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
  z.avail_in = static_cast<uInt>(text.size());
  z.next_out = reinterpret_cast<Bytef*>(packed.data());
  z.avail_out = static_cast<uInt>(packed.size());
  const int status = deflate(&z, Z_FINISH);
  packed.resize(z.total_out);
  deflateEnd(&z);
  REQUIRE(status == Z_STREAM_END);
  return packed;
}

const char* const k_triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

// An OBJ file holding `mesh`. Nine significant digits identify every float, so reading the
// text back must give the very same floats. With `relative`, faces use negative indices.
std::string to_obj_text(const ch04::Mesh& mesh, bool relative) {
  std::string text = "# written by test_ch05\n";
  std::array<char, 160> line{};
  for (const Vec3f& p : mesh.vertices) {
    std::snprintf(line.data(), line.size(), "v %.9g %.9g %.9g\n", static_cast<double>(p.x),
                  static_cast<double>(p.y), static_cast<double>(p.z));
    text += line.data();
  }
  const int n = static_cast<int>(mesh.vertices.size());
  const int shift = relative ? -n : 1; // after the last vertex, index i is i - n
  for (const ch04::IndexedTriangle& t : mesh.triangles) {
    std::snprintf(line.data(), line.size(), "f %d %d %d\n", t.v0 + shift, t.v1 + shift,
                  t.v2 + shift);
    text += line.data();
  }
  return text;
}

} // namespace

TEST_CASE("a quad and a pentagon become fans around their first corner", "[ch05]") {
  const ObjMesh mesh = load_obj(corpus_path("good_quad_pentagon.obj"));
  CHECK(mesh.geometry.vertices.size() == 9);
  CHECK(as_arrays(mesh.geometry.triangles) ==
        Triangles{{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}, {4, 7, 8}});
  CHECK(mesh.bounds_min == Vec3f{0, 0, 0});
  CHECK(mesh.bounds_max == Vec3f{3.5f, 2, 0});
  CHECK(mesh.material_ids == std::vector<int>(5, -1));
  CHECK(mesh.material_names.empty());
  CHECK(mesh.normals.empty());
  CHECK(mesh.normal_indices.empty());
  CHECK(mesh.texcoords.empty());
  CHECK(mesh.texcoord_indices.empty());
  CHECK(mesh.object_count == 1);
  CHECK(mesh.degenerate_triangle_count == 0);
}

TEST_CASE("relative indices count back from the line they are on", "[ch05]") {
  const ObjMesh mesh = load_obj(corpus_path("good_negative_indices.obj"));
  CHECK(as_arrays(mesh.geometry.triangles) == Triangles{{0, 1, 2}, {0, 2, 3}, {0, 1, 2}});
  CHECK(as_arrays(mesh.texcoord_indices) == Triangles{{-1, -1, -1}, {-1, -1, -1}, {0, 1, 2}});
  CHECK(as_arrays(mesh.normal_indices) == Triangles{{-1, -1, -1}, {-1, -1, -1}, {0, 0, 0}});
  CHECK(mesh.texcoords == std::vector<Vec2f>{{0, 0}, {1, 0}, {0, 1}});
  CHECK(mesh.normals == std::vector<Vec3f>{{0, 0, 1}});
  CHECK(mesh.bounds_min == Vec3f{0, 0, 0});
  CHECK(mesh.bounds_max == Vec3f{1, 1, 1});
}

TEST_CASE("several objects and groups in one file keep their faces in file order", "[ch05]") {
  const ObjMesh mesh = load_obj(corpus_path("good_objects_groups.obj"));
  CHECK(as_arrays(mesh.geometry.triangles) ==
        Triangles{{0, 1, 2}, {0, 2, 3}, {1, 2, 3}, {0, 1, 3}});
  // first, part_a, part_b, last: empty_object has no faces and is not counted.
  CHECK(mesh.object_count == 4);
}

TEST_CASE("material ids per triangle come from the .mtl file next to the OBJ", "[ch05]") {
  const ObjMesh mesh = load_obj(corpus_path("good_materials.obj"));
  CHECK(mesh.material_names == std::vector<std::string>{"red", "blue"});
  // no usemtl yet, red, blue (a quad: two triangles), an unknown name, red again
  CHECK(mesh.material_ids == std::vector<int>{-1, 0, 1, 1, -1, 0});
  CHECK(mesh.geometry.triangles.size() == 6);
  CHECK(mesh.object_count == 1);
}

TEST_CASE("a missing material library is not an error: its faces get material id -1",
          "[ch05]") {
  const ObjMesh mesh = load_obj(corpus_path("good_missing_mtl.obj"));
  CHECK(mesh.material_ids == std::vector<int>{-1});
  CHECK(mesh.material_names.empty());
  // parse_obj opens no files: the same text as good_materials.obj gives -1 everywhere.
  std::ifstream file(corpus_path("good_materials.obj"), std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(file), {}};
  const ObjMesh parsed = parse(text);
  CHECK(parsed.material_ids == std::vector<int>(6, -1));
  CHECK(parsed.material_names.empty());
  // A material library that is a folder counts as missing too.
  TempFolder folder("rt_ch05", "mtl_folder");
  std::filesystem::create_directory(folder.path("lib.mtl"));
  const std::string path =
      folder.write("a.obj", std::string("mtllib lib.mtl\nusemtl red\n") + k_triangle);
  CHECK(load_obj(path).material_ids == std::vector<int>{-1});
}

TEST_CASE("normal and texture coordinate indices are -1 where a corner has none", "[ch05]") {
  const ObjMesh mesh = load_obj(corpus_path("good_normals_texcoords.obj"));
  CHECK(as_arrays(mesh.geometry.triangles) ==
        Triangles{{0, 1, 2}, {0, 2, 3}, {0, 2, 3}, {0, 1, 3}});
  CHECK(as_arrays(mesh.texcoord_indices) ==
        Triangles{{0, 1, 2}, {-1, -1, -1}, {0, 2, 1}, {-1, -1, -1}});
  CHECK(as_arrays(mesh.normal_indices) ==
        Triangles{{0, 0, 0}, {1, 1, 1}, {-1, -1, -1}, {-1, -1, -1}});
  CHECK(mesh.normals == std::vector<Vec3f>{{0, 0, 1}, {0, 0, -1}});
  CHECK(mesh.texcoords == std::vector<Vec2f>{{0, 0}, {1, 0}, {1, 1}});
  // Normals in the file but none used: still one (-1, -1, -1) per triangle.
  const ObjMesh unused = parse(std::string("vn 0 0 1\n") + k_triangle);
  CHECK(as_arrays(unused.normal_indices) == Triangles{{-1, -1, -1}});
}

TEST_CASE("degenerate triangles are valid geometry: kept and counted", "[ch05]") {
  const ObjMesh mesh = load_obj(corpus_path("good_degenerate.obj"));
  CHECK(as_arrays(mesh.geometry.triangles) == Triangles{{0, 1, 3}, {0, 1, 2}, {0, 0, 3}});
  CHECK(mesh.degenerate_triangle_count == 2); // collinear corners; a repeated corner
  CHECK(mesh.bounds_max == Vec3f{2, 1, 0});
}

TEST_CASE("a byte order mark, CRLF line endings, tabs and trailing spaces", "[ch05]") {
  const ObjMesh mesh = load_obj(corpus_path("good_bom_crlf.obj"));
  CHECK(as_arrays(mesh.geometry.triangles) == Triangles{{0, 1, 2}});
  CHECK(mesh.geometry.vertices == std::vector<Vec3f>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  // Line numbers count a CRLF once: the error is on line 3.
  CHECK_THAT(parse_error("v 0 0 0\r\nv 1 0 0\r\nf 1 2 3\r\n"),
             rt::testing::contains("test.obj:3: face index 3 is out of range (2 vertices)"));
}

TEST_CASE("positive indices may name vertices defined further down the file", "[ch05]") {
  const ObjMesh mesh = load_obj(corpus_path("good_forward_reference.obj"));
  CHECK(as_arrays(mesh.geometry.triangles) == Triangles{{0, 1, 2}});
  CHECK(mesh.bounds_max == Vec3f{1, 1, 0});
}

TEST_CASE("OBJ statements a triangle mesh does not use are skipped", "[ch05]") {
  const ObjMesh mesh = load_obj(corpus_path("good_unused_statements.obj"));
  CHECK(as_arrays(mesh.geometry.triangles) == Triangles{{0, 1, 2}});
}

// The work this course follows got two things wrong in its loader; these tests pin both.

TEST_CASE("regression: OBJ indices count from 1, tinyobjloader's already from 0", "[ch05]") {
  // Subtracting 1 a second time shifts every triangle one vertex down (and index 1 to -1).
  const ObjMesh mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 2 3 4\nf 1 2 3\n");
  CHECK(as_arrays(mesh.geometry.triangles) == Triangles{{1, 2, 3}, {0, 1, 2}});
  const ch04::TriangleF first = mesh.geometry.triangle(0);
  CHECK(first.v0 == Vec3f{1, 0, 0});
  CHECK(first.v1 == Vec3f{0, 1, 0});
  CHECK(first.v2 == Vec3f{0, 0, 1});
  CHECK(mesh.bounds_min == Vec3f{0, 0, 0});
}

TEST_CASE("regression: faces use vertices out of file order and share them", "[ch05]") {
  // A square pyramid whose five vertices are listed in no particular order. Reading the
  // vertices three at a time in file order, as if each face owned the next three, gives
  // different triangles (and runs out of vertices after the first).
  const ObjMesh mesh = load_obj(corpus_path("good_out_of_order.obj"));
  CHECK(as_arrays(mesh.geometry.triangles) ==
        Triangles{{2, 3, 0}, {3, 1, 0}, {1, 4, 0}, {4, 2, 0}, {2, 4, 1}, {2, 1, 3}});
  const Vec3f apex{0, 0, 1};
  const std::array<Vec3f, 4> base_corners_in_face_order = {Vec3f{-1, -1, 0}, Vec3f{1, -1, 0},
                                                           Vec3f{1, 1, 0}, Vec3f{-1, 1, 0}};
  for (int i = 0; i < 4; ++i) {
    const ch04::TriangleF side = mesh.geometry.triangle(i);
    CHECK(side.v0 == base_corners_in_face_order[i]);
    CHECK(side.v1 == base_corners_in_face_order[(i + 1) % 4]);
    CHECK(side.v2 == apex);
  }
  CHECK(mesh.geometry.triangle(4).v1 == Vec3f{-1, 1, 0});
  // Every vertex is shared, and the pyramid is closed and consistently oriented.
  CHECK(ch04::count_unpaired_edges(mesh.geometry) == 0);
  CHECK(mesh.bounds_min == Vec3f{-1, -1, 0});
  CHECK(mesh.bounds_max == Vec3f{1, 1, 1});
}

TEST_CASE("an icosphere written as OBJ text loads back bit for bit", "[ch05]") {
  const ch04::Mesh sphere = ch04::make_icosphere(3, {1.5, -2.25, 1e3}, 0.7);
  for (const bool relative : {false, true}) {
    CAPTURE(relative);
    const ObjMesh mesh = parse(to_obj_text(sphere, relative));
    CHECK(mesh.geometry.vertices == sphere.vertices);
    CHECK(as_arrays(mesh.geometry.triangles) == as_arrays(sphere.triangles));
    CHECK(ch04::count_unpaired_edges(mesh.geometry) == 0);
    CHECK(mesh.degenerate_triangle_count == 0);
    CHECK(rt::testing::mesh_invariant_violation(mesh).empty());
  }
}

TEST_CASE("numbers: plain decimal notation only, finite as a float", "[ch05]") {
  const auto x_of = [](const std::string& word) {
    return parse("v " + word + " 0 0\nv 1 2 0\nv 0 1 0\nf 1 2 3\n").geometry.vertices[0].x;
  };
  CHECK(x_of("1") == 1.0f);
  CHECK(x_of("-1.5") == -1.5f);
  CHECK(x_of("+.5") == 0.5f);
  CHECK(x_of("5.") == 5.0f);
  CHECK(x_of("2.5E+2") == 250.0f);
  CHECK(x_of("0.1") == 0.1f);
  CHECK(x_of("1e10") == 1e10f); // the largest supported coordinate (supported_range.h)
  CHECK(x_of("1e-50") == 0.0f); // below the smallest float: rounds to 0, like any float code
  const auto error = [](const std::string& word) {
    return parse_error("v " + word + " 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  };
  CHECK_THAT(error("1,5"),
             rt::testing::contains("test.obj:1: coordinate '1,5' is not a number"));
  CHECK_THAT(error("1e"), rt::testing::contains("'1e' is not a number"));
  CHECK_THAT(error("."), rt::testing::contains("'.' is not a number"));
  CHECK_THAT(error("--1"), rt::testing::contains("'--1' is not a number"));
  CHECK_THAT(error("1.2.3"), rt::testing::contains("'1.2.3' is not a number"));
  CHECK_THAT(error("Infinity"), rt::testing::contains("'Infinity' is not a finite number"));
  CHECK_THAT(error("-NaN"), rt::testing::contains("'-NaN' is not a finite number"));
  CHECK_THAT(error("3.5e38"), rt::testing::contains("'3.5e38' is too large for a float"));
  CHECK_THAT(error("1.5e10"), rt::testing::contains("'1.5e10' is outside the supported range"));
  CHECK_THAT(error("1e-400"), rt::testing::contains("has an exponent beyond 99"));
  CHECK_THAT(error("0." + std::string(999, '0') + "1"),
             rt::testing::contains("is too long (over 1000 characters)"));
  CHECK_THAT(parse_error(std::string("vt 0 1e39\n") + k_triangle),
             rt::testing::contains("test.obj:1: texture coordinate '1e39' is too large"));
  CHECK_THAT(parse_error(std::string("vt\n") + k_triangle),
             rt::testing::contains("test.obj:1: 'vt' needs 1 to 3 numbers (u v w)"));
  CHECK_THAT(parse_error(std::string("v 1 2 3 4 5 6 7\n") + k_triangle),
             rt::testing::contains("test.obj:1: 'v' needs x y z"));
}

TEST_CASE("a .gz file loads the same as the plain file, whatever it is called", "[ch05]") {
  TempFolder folder("rt_ch05", "gzip");
  const ch04::Mesh box = ch04::make_box({-1, -2, -3}, {4, 5, 6}, 3);
  const std::string text = to_obj_text(box, false);
  const ObjMesh plain = parse(text);
  for (const char* file : {"box.obj.gz", "box_without_gz_ending.obj"}) {
    CAPTURE(file);
    const ObjMesh packed = load_obj(folder.write(file, gzip(text)));
    CHECK(packed.geometry.vertices == plain.geometry.vertices);
    CHECK(as_arrays(packed.geometry.triangles) == as_arrays(plain.geometry.triangles));
    CHECK(packed.bounds_min == Vec3f{-1, -2, -3});
    CHECK(packed.bounds_max == Vec3f{4, 5, 6});
  }
  // Plain text named .gz is plain text: the first two bytes decide, not the name.
  CHECK(load_obj(folder.write("plain.obj.gz", text)).geometry.vertices ==
        plain.geometry.vertices);
  // parse_obj unpacks gzip bytes too; two members in a row are one file.
  CHECK(parse(gzip(text)).geometry.triangles.size() == plain.geometry.triangles.size());
  const ObjMesh two = parse(gzip("v 0 0 0\nv 1 0 0\n") + gzip("v 0 1 0\nf 1 2 3\n"));
  CHECK(as_arrays(two.geometry.triangles) == Triangles{{0, 1, 2}});
  // Errors inside gzip data still name their line.
  CHECK_THAT(parse_error(gzip("v 0 0 0\nv 1 0 0\nf 1 2 3\n")),
             rt::testing::contains("test.obj:3: face index 3 is out of range (2 vertices)"));
  CHECK_THAT(parse_error(gzip("")), rt::testing::contains("test.obj: the file is empty"));
  CHECK_THAT(parse_error(gzip(k_triangle).substr(0, 12)),
             rt::testing::contains("test.obj: truncated gzip data"));
}

TEST_CASE("a gzip bomb stops at LoadLimits::max_file_bytes while it unpacks", "[ch05]") {
  // 64 MiB of spaces pack into about 64 KiB.
  const std::string bomb = gzip(std::string(64 << 20, ' ') + k_triangle);
  CHECK(bomb.size() < (256 << 10));
  LoadLimits limits;
  limits.max_file_bytes = 1 << 20;
  CHECK_THAT(parse_error(bomb, limits),
             rt::testing::contains("test.obj: decompresses to more than "
                                   "LoadLimits::max_file_bytes (1048576 bytes)"));
  TempFolder folder("rt_ch05", "bomb");
  const std::string path = folder.write("bomb.obj.gz", bomb);
  CHECK_THAT(error_of([&] { load_obj(path, limits); }),
             rt::testing::contains("bomb.obj.gz: decompresses to more than"));
  // With the default limit (2 GiB) the same file is just a large one.
  CHECK(load_obj(path).geometry.triangles.size() == 1);
}

TEST_CASE("LoadLimits caps vertices, normals, texture coordinates, triangles and bytes",
          "[ch05]") {
  LoadLimits limits;
  limits.max_vertices = 3;
  CHECK(parse(k_triangle, limits).geometry.vertices.size() == 3);
  CHECK_THAT(
      parse_error(std::string("v 0 0 1\n") + k_triangle, limits),
      rt::testing::contains("test.obj:4: more than 3 vertices (LoadLimits::max_vertices)"));
  CHECK_THAT(
      parse_error(std::string("vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\n") + k_triangle, limits),
      rt::testing::contains("test.obj:4: more than 3 normals"));
  CHECK_THAT(parse_error(std::string("vt 0\nvt 0\nvt 0\nvt 0\n") + k_triangle, limits),
             rt::testing::contains("test.obj:4: more than 3 texture coordinates"));
  limits = {};
  limits.max_triangles = 2;
  const std::string quad_and_triangle =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 3\n";
  CHECK_THAT(
      parse_error(quad_and_triangle, limits),
      rt::testing::contains("test.obj:6: more than 2 triangles (LoadLimits::max_triangles)"));
  limits = {};
  limits.max_file_bytes = 10;
  CHECK_THAT(
      parse_error(k_triangle, limits),
      rt::testing::contains("test.obj: larger than LoadLimits::max_file_bytes (10 bytes)"));
  TempFolder folder("rt_ch05", "limits");
  const std::string path = folder.write("a.obj", k_triangle);
  CHECK_THAT(error_of([&] { load_obj(path, limits); }),
             rt::testing::contains("a.obj: larger than LoadLimits::max_file_bytes (10 bytes)"));
  // Limits above what an int index can address are lowered to it, not trusted.
  limits = {};
  limits.max_vertices = limits.max_triangles = 1LL << 40;
  CHECK(parse(k_triangle, limits).geometry.triangles.size() == 1);
}

TEST_CASE("the file system: missing, a folder, a device, unreadable, empty", "[ch05]") {
  TempFolder folder("rt_ch05", "files");
  const std::string missing = folder.path("missing.obj");
  CHECK(error_of([&] { load_obj(missing); }) ==
        missing + ": cannot open (No such file or directory)");
  CHECK(error_of([&] { load_obj(folder.path("")); }) ==
        folder.path("") + ": is a directory, not an OBJ file");
  if (std::filesystem::exists("/dev/zero")) {
    CHECK(error_of([] { load_obj("/dev/zero"); }) == "/dev/zero: is not a regular file");
  }
  if (std::filesystem::exists("/proc/self/status")) {
    // A file whose reported size (0) is wrong: the size cap holds while it is read.
    LoadLimits limits;
    limits.max_file_bytes = 16;
    CHECK(error_of([&] { load_obj("/proc/self/status", limits); }) ==
          "/proc/self/status: larger than LoadLimits::max_file_bytes (16 bytes)");
    CHECK(error_of([] { load_obj("/proc/self/status"); }) ==
          "/proc/self/status:1: unknown statement 'Name:' (not OBJ)");
  }
  const std::string empty = folder.write("empty.obj", "");
  CHECK(error_of([&] { load_obj(empty); }) == empty + ": the file is empty");
  const std::string locked = folder.write("locked.obj", k_triangle);
  std::filesystem::permissions(locked, std::filesystem::perms::none);
  if (::geteuid() != 0) { // root reads any file: nothing to test there
    CHECK(error_of([&] { load_obj(locked); }) == locked + ": cannot open (Permission denied)");
  }
  CHECK_THAT(parse_error("# only a comment\n"),
             rt::testing::contains("test.obj: no faces (0 vertices)"));
}

TEST_CASE("long lines: a long comment, a face with many corners, a long garbage word",
          "[ch05]") {
  // A 16 MiB comment line costs time in proportion, and later line numbers stay right.
  const std::string comment = "#" + std::string(16 << 20, 'c') + "\n";
  CHECK(parse(comment + k_triangle).geometry.triangles.size() == 1);
  CHECK_THAT(parse_error(comment + "v 0 0 0\nf 1 1 2\n"),
             rt::testing::contains("test.obj:3: face index 2 is out of range (1 vertex)"));
  // One face with 100 000 corners (a circle): 99 998 triangles in a fan.
  const int corners = 100000;
  std::string circle;
  for (int i = 0; i < corners; ++i)
    circle.append("v ").append(std::to_string(i % 7)).append(i % 5 ? " 1 2\n" : " 0 2\n");
  circle += "f";
  for (int i = 1; i <= corners; ++i) circle.append(" ").append(std::to_string(i));
  const ObjMesh fan = parse(circle + "\n");
  REQUIRE(fan.geometry.triangles.size() == corners - 2);
  CHECK(as_arrays({fan.geometry.triangles.back()}) == Triangles{{0, corners - 2, corners - 1}});
  // A garbage word of 1 MiB: the message shows its first 40 characters.
  const std::string message = parse_error("v 0 0 " + std::string(1 << 20, 'z') + "\n");
  CHECK(message.size() < 120);
  CHECK_THAT(message, rt::testing::contains("'zzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzz...'"));
}

TEST_CASE("faces with more than 255 corners keep all their corners", "[ch05]") {
  // tinyobjloader stores a face's corner count in one byte: 256 corners wrap around to 0.
  for (const int corners : {255, 256, 300, 511, 512, 513}) {
    CAPTURE(corners);
    std::string text;
    for (int i = 0; i < corners; ++i)
      text.append("v ").append(std::to_string(i)).append(i % 2 ? " 1 0\n" : " 0 0\n");
    text += "f";
    for (int i = 1; i <= corners; ++i) text.append(" ").append(std::to_string(i));
    text += "\nf 1 2 3\n";
    const ObjMesh mesh = parse(text);
    REQUIRE(static_cast<int>(mesh.geometry.triangles.size()) == corners - 2 + 1);
    CHECK(as_arrays({mesh.geometry.triangles[corners - 3]}) ==
          Triangles{{0, corners - 2, corners - 1}});
    CHECK(as_arrays({mesh.geometry.triangles.back()}) == Triangles{{0, 1, 2}});
  }
}
