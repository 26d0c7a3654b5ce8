// Chapter 04: --variant moller-trumbore|watertight, the flag every triangle chapter takes to
// choose the intersection test its image uses.
#pragma once

#include <map>
#include <string>

#include <CLI/CLI.hpp>

#include "triangles.h"

namespace rt::ch04 {

inline void add_triangle_variant_option(CLI::App& app, TriangleVariant& variant) {
  app.add_option("--variant", variant, "Intersection used for the image")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, TriangleVariant>{
              {"moller-trumbore", TriangleVariant::moller_trumbore},
              {"watertight", TriangleVariant::watertight}},
          CLI::ignore_case))
      ->default_str(variant == TriangleVariant::watertight ? "watertight" : "moller-trumbore");
}

} // namespace rt::ch04
