// Chapter 12: scenes made by code, for the tests, the furnace and the book's series: a sphere
// of one material alone under a uniform sky, and a row of spheres of one material from smooth
// to rough. The course's material room comes from assets/ (tools/make-material-room.py).
#pragma once

#include <string>

#include "material_scene.h"

namespace rt::ch12 {

// A few materials by name: "white" (Lambertian, albedo 0.8), "glass" (smooth, ior 1.5),
// "rough-glass", "white-metal" (a conductor that reflects everything: Schlick F0 = 1), "gold"
// and "copper" (conductors by their complex index at red, green and blue, from measured
// data), "plastic" (glTF's dielectric over a red diffuse base). `roughness` in [0, 1] replaces
// the material's own (0 for glass, 0.3 for the others; Lambertian has none); below 0 keeps it.
// Throws UsageError naming the choices for any other name.
Material named_material(const std::string& name, float roughness = -1.0f);
// "white, glass, rough-glass, ...": the names named_material knows.
std::string material_names();

// [listing:furnace_scene]
// The white furnace of chapter 12: a sphere of radius 1 at the origin, made of `material`
// (an icosphere of 20 * 4^subdivisions faces, its front faces outside), under a uniform sky of
// radiance `sky`, and nothing else. A material that neither absorbs nor emits is invisible in
// it: every path that leaves the sphere sees the sky, so every pixel is `sky`.
MaterialScene make_sphere_in_sky(const Material& material, int subdivisions, float sky);
// [/listing:furnace_scene]
// Its camera: on +z, the sphere filling the middle half of the image.
CameraSpec sphere_camera();

// Five spheres of `material` side by side, roughness 0, 0.1, 0.25, 0.5 and 1 from left to
// right, on a grey Lambertian floor with a dark checkered wall behind them (so that a smooth
// sphere shows what it reflects or refracts), lit by a grey sky and a sun.
MaterialScene make_roughness_series(const Material& material);
CameraSpec roughness_series_camera();

} // namespace rt::ch12
