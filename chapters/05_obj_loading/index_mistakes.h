// Chapter 05: the original loader's two index mistakes, made again on purpose so that their
// pictures can be seen (ch05_obj_loading --index-mistake). A correct load, then the triangles
// a loader with the mistake would have built from the same file.
#pragma once

#include <string_view>

#include "mesh_render.h"

namespace rt::ch05 {

enum class IndexMistake {
  none,       // the loader as it is
  minus_one,  // OBJ's 1 subtracted again from tinyobjloader's 0-based indices
  file_order, // triangle i taken to be vertices 3i, 3i+1, 3i+2 (a "triangle soup")
};

// "none", "minus-one" or "file-order"; UsageError naming the text otherwise.
IndexMistake parse_index_mistake(std::string_view text);

// `scene`'s triangles as the mistaken loader would have made them. minus_one moves every
// corner to the previous vertex; the first vertex's index would then be -1, a read before the
// array, and wraps round to the last vertex here instead. file_order makes one triangle per
// three vertices, in file order (no more triangles than the file has), each with the material
// of the triangle it replaces.
void repeat_index_mistake(ch04::TriangleScene& scene, IndexMistake mistake);

} // namespace rt::ch05
