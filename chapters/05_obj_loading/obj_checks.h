// Chapter 05: OBJ text checked line by line before tinyobjloader reads it, so that every
// problem is reported with its line number and tinyobjloader only sees text it reads right.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "obj_loader.h"

namespace rt::ch05 {

// What the checks counted in a file that passed them. tinyobjloader's result must agree.
struct ObjCounts {
  long long positions = 0, texcoords = 0, normals = 0; // `v`, `vt` and `vn` statements
  long long faces = 0, corners = 0, triangles = 0;     // triangles: once faces become fans
  // tinyobjloader keeps a face's corner count in an unsigned char, so a face with more than
  // 255 corners comes back with its count wrapped around. Those faces are listed here, as
  // (face number from 0, corners); they are rare, so the list stays short.
  std::vector<std::pair<long long, long long>> large_faces;
};

// Checks every line of `text`, or throws rt::InputError with "name:line: what is wrong".
// Statements a triangle mesh does not use (lines, curves, smoothing groups...) are overwritten
// with spaces, which keeps every line on its line number, so tinyobjloader sees only what was
// checked. A UTF-8 byte order mark at the start is blanked too. read_up_to, when given, is
// called now and then with the offset the checks have reached (for a progress line).
ObjCounts check_obj_lines(std::string& text, const std::string& name, const LoadLimits& limits,
                          const std::function<void(std::size_t)>& read_up_to = {});

} // namespace rt::ch05
