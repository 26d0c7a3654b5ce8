// Chapter 06: what lights a scene. Directional lights (the sun: one direction everywhere),
// point lights (a bulb: light falls off with the square of the distance) and an ambient term,
// a constant that stands in for all the light bounced around the scene, which this course
// does not trace yet. Each surface has one colour, its albedo, from a small palette.
#pragma once

#include "rt/vec.h"

namespace rt::ch06 {

inline constexpr int k_max_lights = 4;   // of each kind: they travel as a kernel argument
inline constexpr int k_palette_size = 8; // albedos a scene can use

struct DirectionalLight {
  Vec3f direction; // unit, from the surface towards the light
  Vec3f radiance;  // the irradiance it gives a surface that faces it squarely
};

struct PointLight {
  Vec3f position;  // where the bulb is
  Vec3f intensity; // the irradiance at distance 1 on a surface that faces it
};

// The lights by value: 12 + 2 * 4 + 4 * 24 + 4 * 24 = 212 bytes of kernel argument.
struct Lights {
  Vec3f ambient;                                // added to every lit or shadowed surface
  int directional_count = 0;                    // used entries of `directional`
  int point_count = 0;                          // used entries of `point`
  DirectionalLight directional[k_max_lights]{}; // the first directional_count are used
  PointLight point[k_max_lights]{};             // the first point_count are used
};

// Albedo (the fraction of light a surface reflects, per channel) by palette slot.
struct Palette {
  Vec3f albedo[k_palette_size]{};
};

} // namespace rt::ch06
