// Chapter 04: the closest hit of a ray against a mesh, the record every later chapter's tracer
// returns and chapter 07's hit files hold. Plain C++ (no CUDA header), so file readers and
// tools can use it alone.
#pragma once

#include <limits>

namespace rt::ch04 {

// The closest hit of a ray: t = +infinity and triangle = -1 for a miss (the layout of the
// benchmark's hit buffer).
struct MeshHit {
  float t = std::numeric_limits<float>::infinity();
  int triangle = -1;
};

} // namespace rt::ch04
