// Chapter 05: the original loader's two index mistakes, repeated for their pictures.
#include "index_mistakes.h"

#include <algorithm>
#include <string>

#include "rt/error.h"

namespace rt::ch05 {

IndexMistake parse_index_mistake(std::string_view text) {
  if (text == "none") return IndexMistake::none;
  if (text == "minus-one") return IndexMistake::minus_one;
  if (text == "file-order") return IndexMistake::file_order;
  throw UsageError("unknown index mistake '" + std::string(text) +
                   "' (none, minus-one, file-order)");
}

void repeat_index_mistake(ch04::TriangleScene& scene, IndexMistake mistake) {
  std::vector<ch04::IndexedTriangle>& triangles = scene.mesh.triangles;
  const int vertex_count = static_cast<int>(scene.mesh.vertices.size());
  if (mistake == IndexMistake::minus_one) {
    const auto previous = [&](int v) { return v == 0 ? vertex_count - 1 : v - 1; };
    for (ch04::IndexedTriangle& t : triangles)
      t = {previous(t.v0), previous(t.v1), previous(t.v2)};
  } else if (mistake == IndexMistake::file_order) {
    const std::size_t soup = std::min<std::size_t>(vertex_count / 3, triangles.size());
    triangles.resize(soup);
    scene.object.resize(soup);
    for (std::size_t i = 0; i < soup; ++i) {
      const int first = static_cast<int>(3 * i);
      triangles[i] = {first, first + 1, first + 2};
    }
  }
}

} // namespace rt::ch05
