// Chapter 05 tests: the corpus of hostile files. Each bad_* file attacks the loader in one way
// (its first line says how) and must end in one error line that names the file, the line and
// the problem. The good_* files must load. Every file of the corpus is named here, so a file
// added without an expectation fails the last test. The fuzzer starts from the same files.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "mesh_invariants.h"
#include "obj_loader.h"
#include "rt/error.h"

using namespace rt;
using namespace rt::ch05;

namespace {

std::string corpus_path(const std::string& file) {
  return std::string(RT_CH05_CORPUS_DIR) + "/" + file;
}

struct HostileFile {
  const char* file;
  const char* expected; // a substring of the error: "file:line: what"
};

// clang-format off
const std::vector<HostileFile> k_hostile_files = {
  {"bad_binary_garbage.obj",       "bad_binary_garbage.obj:2: NUL byte: this is a binary file"},
  {"bad_binary_high_bytes.obj",    "bad_binary_high_bytes.obj:2: unknown statement '\\x80\\x81"},
  {"bad_continuation.obj",         "bad_continuation.obj:5: a line continued with '\\' is not"},
  {"bad_corrupt.obj.gz",           "bad_corrupt.obj.gz: corrupt gzip data (zlib: "},
  {"bad_crc.obj.gz",               "bad_crc.obj.gz: corrupt gzip data (zlib: incorrect data check)"},
  {"bad_exponent_overflow.obj",    "bad_exponent_overflow.obj:2: coordinate '0e2147483649' has an "
                                   "exponent beyond 99"},
  {"bad_face_index_too_big.obj",   "bad_face_index_too_big.obj:12: face index 9 is out of range "
                                   "(8 vertices)"},
  {"bad_face_index_zero.obj",      "bad_face_index_zero.obj:5: face index 0 is invalid: OBJ "
                                   "indices count from 1"},
  {"bad_face_negative_too_far.obj","bad_face_negative_too_far.obj:5: face index -4 is out of "
                                   "range (3 vertices before this line)"},
  {"bad_face_no_corners.obj",      "bad_face_no_corners.obj:6: face has 0 corners; a face needs "
                                   "at least 3"},
  {"bad_face_non_numeric.obj",     "bad_face_non_numeric.obj:5: face corner 'two' is malformed"},
  {"bad_face_two_corners.obj",     "bad_face_two_corners.obj:5: face has 2 corners"},
  {"bad_float_overflow.obj",       "bad_float_overflow.obj:4: coordinate '1e39' is too large for "
                                   "a float"},
  {"bad_four_part_corner.obj",     "bad_four_part_corner.obj:5: face corner '1/1/1/1' is malformed"},
  {"bad_garbage_number.obj",       "bad_garbage_number.obj:3: coordinate 'abc' is not a number"},
  {"bad_glued_index.obj",          "bad_glued_index.obj:5: face corner '1x' is malformed"},
  {"bad_gzip_inner_error.obj.gz",  "bad_gzip_inner_error.obj.gz:5: face index 7 is out of range "
                                   "(3 vertices)"},
  {"bad_hex_float.obj",            "bad_hex_float.obj:3: coordinate '0x1p3' is not a number"},
  {"bad_index_wraps_int.obj",      "bad_index_wraps_int.obj:5: face index 4294967298 is out of "
                                   "range (3 vertices)"},
  {"bad_inf.obj",                  "bad_inf.obj:3: coordinate '-inf' is not a finite number"},
  {"bad_lone_cr.obj",              "bad_lone_cr.obj:4: face index 3 is out of range (2 vertices)"},
  {"bad_long_garbage_token.obj",   "bad_long_garbage_token.obj:3: coordinate "
                                   "'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx...' is not a number"},
  {"bad_nan.obj",                  "bad_nan.obj:4: coordinate 'nan' is not a finite number"},
  {"bad_negative_counts_from_line.obj", "bad_negative_counts_from_line.obj:4: face index -3 is "
                                   "out of range (2 vertices before this line)"},
  {"bad_no_faces.obj",             "bad_no_faces.obj: no faces (3 vertices)"},
  {"bad_normal_count.obj",         "bad_normal_count.obj:5: 'vn' needs 3 numbers (x y z); this "
                                   "one has 2"},
  {"bad_normal_index_no_normals.obj", "bad_normal_index_no_normals.obj:5: normal index 1 is out "
                                   "of range (0 normals)"},
  {"bad_normal_nan.obj",           "bad_normal_nan.obj:5: normal component 'nan' is not a finite "
                                   "number"},
  {"bad_number_with_suffix.obj",   "bad_number_with_suffix.obj:2: coordinate '1.5abc' is not a "
                                   "number"},
  {"bad_texcoord_garbage.obj",     "bad_texcoord_garbage.obj:5: texture coordinate 'x' is not a "
                                   "number"},
  {"bad_texcoord_index.obj",       "bad_texcoord_index.obj:6: texture coordinate index 5 is out "
                                   "of range (1 texture coordinate)"},
  {"bad_too_few_coordinates.obj",  "bad_too_few_coordinates.obj:3: 'v' needs x y z"},
  {"bad_trailing_bytes.obj.gz",    "bad_trailing_bytes.obj.gz: unexpected bytes after the end of "
                                   "the gzip data"},
  {"bad_trailing_slash.obj",       "bad_trailing_slash.obj:8: face corner '1/' is malformed"},
  {"bad_truncated.obj.gz",         "bad_truncated.obj.gz: truncated gzip data"},
  {"bad_unknown_statement.obj",    "bad_unknown_statement.obj:3: unknown statement 'V'"},
};
// clang-format on

// The good files, each tested for its exact mesh in test_ch05.cpp; here they must load and
// satisfy the invariants. good_materials.mtl is not an OBJ file but a material library.
const std::vector<std::string> k_good_files = {
    "good_bom_crlf.obj",          "good_degenerate.obj",     "good_forward_reference.obj",
    "good_materials.obj",         "good_missing_mtl.obj",    "good_negative_indices.obj",
    "good_normals_texcoords.obj", "good_objects_groups.obj", "good_out_of_order.obj",
    "good_quad_pentagon.obj",     "good_two_members.obj.gz", "good_unused_statements.obj"};
const std::vector<std::string> k_support_files = {"good_materials.mtl"};

std::string load_error(const std::string& path) {
  try {
    load_obj(path);
  } catch (const InputError& error) {
    return error.what();
  }
  return "(no error)";
}

} // namespace

TEST_CASE("every hostile file of the corpus ends in one error line naming file and line",
          "[ch05]") {
  for (const HostileFile& hostile : k_hostile_files) {
    const std::string path = corpus_path(hostile.file);
    const std::string message = load_error(path);
    CAPTURE(hostile.file, message);
    CHECK_THAT(message, rt::testing::contains(hostile.expected));
    CHECK_THAT(message, rt::testing::starts_with(path));
    CHECK(message.find('\n') == std::string::npos);
    CHECK(message.size() < path.size() + 160);
  }
}

TEST_CASE("every good file of the corpus loads into a consistent mesh", "[ch05]") {
  for (const std::string& file : k_good_files) {
    CAPTURE(file);
    const ObjMesh mesh = load_obj(corpus_path(file));
    CHECK(rt::testing::mesh_invariant_violation(mesh).empty());
  }
}

TEST_CASE("every corpus file is named by a test", "[ch05]") {
  std::vector<std::string> named = k_good_files;
  named.insert(named.end(), k_support_files.begin(), k_support_files.end());
  for (const HostileFile& hostile : k_hostile_files) named.emplace_back(hostile.file);
  std::vector<std::string> present;
  for (const auto& entry : std::filesystem::directory_iterator(RT_CH05_CORPUS_DIR)) {
    present.push_back(entry.path().filename().string());
  }
  std::sort(named.begin(), named.end());
  std::sort(present.begin(), present.end());
  CHECK(present == named);
}
