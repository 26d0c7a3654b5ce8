// Chapter 07: the tree checker. The traversal trusts the tree completely (it follows child
// indices and leaf ranges without a bounds check), so every tree the course builds, and every
// way of damaging one the tests can think of, goes through this checker first.
#pragma once

#include <string>
#include <vector>

#include "bvh.h"
#include "mesh_gen.h"

namespace rt::ch07 {

// Everything the traversal relies on, checked against the mesh the tree was built from: each
// triangle in exactly one leaf, copied bit for bit; boxes that contain what lies below them;
// the depth-first layout; depth and leaf sizes within bounds; stats that agree with the tree.
// Returns one line per problem found; empty means valid. Safe on any input: a corrupt tree
// gives problems, never a crash or an endless walk.
std::vector<std::string> check_bvh(const Bvh& bvh, const ch04::Mesh& mesh);

} // namespace rt::ch07
