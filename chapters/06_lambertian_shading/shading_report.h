// Chapter 06: the headless report's rows. Each shading variant (flat or smooth, shadows or
// not) by the kernel specialised on its features and by the all-features kernel, on each
// backend, against the float64 reference; then shadow acne counted on a convex sphere.
#pragma once

#include <string>
#include <vector>

#include "rt/backend.h"
#include "rt/launch.h"
#include "rt/report.h"
#include "shaded_scene.h"

namespace rt::ch06 {

struct Variant {
  bool smooth;
  bool shadows;
};
inline constexpr Variant k_variants[] = {
    {false, false}, {false, true}, {true, false}, {true, true}};

// "smooth, shadows", "flat, no shadows".
std::string variant_name(Variant v);

// Flat and smooth, shadows off and on: each by the specialised and the all-features kernel on
// each backend, against the float64 reference.
void report_variants(const std::vector<Backend>& backends, const ShadedScene& scene,
                     const CameraSpec& spec, Extent extent, int frames, Report& report);

// A convex sphere at scales 1 to 1e6, flat, with shadows, in an image of at most 320x180: any
// shadow ray blocked on a face that faces its light is acne.
void report_acne(const std::vector<Backend>& backends, Extent image,
                 const LightSettings& lights, Report& report);

} // namespace rt::ch06
