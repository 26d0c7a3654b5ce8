// Chapter 06: leaving out what the scene does not need. A kernel is compiled for a set of
// features; the code of a feature that is off is not in it at all, so it takes no registers
// and no branches, and the data only that code reads is never uploaded.
#pragma once

#include <string>

#include "rt/error.h"
#include "rt/hd.h"

namespace rt::ch06 {

enum Feature : unsigned {
  k_smooth_normals = 1u << 0, // normals interpolated from the vertices' (else the face's)
  k_shadows = 1u << 1,        // one shadow ray per light
  k_point_lights = 1u << 2,   // point lights besides the directional ones
};
inline constexpr unsigned k_all_features = k_smooth_normals | k_shadows | k_point_lights;

// [listing:feature_sets]
// A specialised kernel: its features are fixed when it is compiled. Code guarded by
// `if constexpr (F::compiled(feature))` is left out of the kernels that do not use it.
template <unsigned kFeatures> struct Specialised {
  RT_HD static constexpr bool compiled(unsigned feature) { return (kFeatures & feature) != 0; }
  RT_HD static constexpr bool on(unsigned feature) { return compiled(feature); }
};

// The all-features kernel: every feature is compiled in, and the scene's flags decide at run
// time, the way one kernel serves every scene.
struct AllFeatures {
  unsigned flags = 0; // the features this frame uses
  RT_HD static constexpr bool compiled(unsigned) { return true; }
  RT_HD bool on(unsigned feature) const { return (flags & feature) != 0; }
};
// [/listing:feature_sets]

// Calls fn(Specialised<features>{}): one instantiation of fn per possible set, chosen at run
// time by the switch. The set of instantiations is what a build compiles.
template <class Fn> decltype(auto) with_specialised(unsigned features, Fn&& fn) {
  switch (features) {
  case 0:
    return fn(Specialised<0>{});
  case 1:
    return fn(Specialised<1>{});
  case 2:
    return fn(Specialised<2>{});
  case 3:
    return fn(Specialised<3>{});
  case 4:
    return fn(Specialised<4>{});
  case 5:
    return fn(Specialised<5>{});
  case 6:
    return fn(Specialised<6>{});
  case 7:
    return fn(Specialised<7>{});
  default:
    throw Error("no specialised kernel for features " + std::to_string(features));
  }
}
static_assert(k_all_features == 7, "with_specialised() needs a case per feature set");

// "smooth normals, shadows, point lights", or "none".
inline std::string describe_features(unsigned features) {
  std::string text;
  const auto add = [&](unsigned feature, const char* name) {
    if ((features & feature) == 0) return;
    text += text.empty() ? name : std::string(", ") + name;
  };
  add(k_smooth_normals, "smooth normals");
  add(k_shadows, "shadows");
  add(k_point_lights, "point lights");
  return text.empty() ? "none" : text;
}

} // namespace rt::ch06
