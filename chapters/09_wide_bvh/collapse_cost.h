// Chapter 09: the arithmetic of the SAH collapse (collapse.cpp), one binary node at a time, in
// RT_HD code: chapter 10's parallel collapse runs the very same operations on the GPU, so both
// make the same choices, bit for bit, from the same tree.
#pragma once

#include <cstdint>
#include <limits>

#include "bvh.h"
#include "rt/hd.h"
#include "wide_bvh.h"

namespace rt::ch09 {

// The cost model of the SAH collapse, the paper's constants: a node visit costs 1, a triangle
// test 0.3, each weighted by the chance that a ray through the root enters the box.
inline constexpr double k_node_cost = 1.0;
inline constexpr double k_triangle_cost = 0.3;

// [listing:cost_row]
// A binary node's row is cost[i - 1], i = 1..width: the least cost of its triangles as at most
// i children of a wide node. Its two children's rows give its spread: for j = 2..width,
// spread[j] = min over 0 < k < j of left[k - 1] + right[j - k - 1], the least cost of j
// children shared between the two sides, and k[j] the left side's share (the smallest k on a
// tie).
template <int Width> struct CostSpread {
  double spread[Width + 1];
  std::uint8_t k[Width + 1];
};

template <int Width>
RT_HD inline void spread_rows(const double* left, const double* right, int width,
                              CostSpread<Width>& out) {
  for (int j = 2; j <= width; ++j) {
    double best = std::numeric_limits<double>::infinity();
    int best_k = 0;
    for (int k = 1; k < j; ++k) {
      const double c = left[k - 1] + right[j - k - 1];
      if (c < best) {
        best = c;
        best_k = k;
      }
    }
    if (best_k == 0) { // every sum infinite: the first share, so no side is left no child
      best = left[0] + right[j - 2];
      best_k = 1;
    }
    out.spread[j] = best;
    out.k[j] = static_cast<std::uint8_t>(best_k);
  }
}

// The choices recorded for a node: split[i - 1] the left share of i children, or 0 where fewer
// children cost no more; as_leaf: one child means a leaf, not a wide node.
struct CostChoices {
  std::uint8_t split[k_slots];
  bool as_leaf;
};

// The row of a node of `area` (half area of its box) from its spread. `leaf`: its cost as one
// wide leaf, A * triangles * k_triangle_cost, where `can_be_leaf` (it has few enough
// triangles), else infinity; a node that cannot be a leaf never is one, even were its interior
// cost infinite too.
template <int Width>
RT_HD inline void finish_row(double area, double leaf, bool can_be_leaf,
                             const CostSpread<Width>& p, int width, double* cost,
                             CostChoices& choices) {
  const double interior = area * k_node_cost + p.spread[width];
  choices.as_leaf = can_be_leaf && leaf <= interior;
  cost[0] = interior < leaf ? interior : leaf;
  choices.split[0] = 0;
  for (int i = 2; i <= width; ++i) {
    const bool fewer = cost[i - 2] <= p.spread[i]; // on a tie, fewer children
    cost[i - 1] = fewer ? cost[i - 2] : p.spread[i];
    choices.split[i - 1] = static_cast<std::uint8_t>(fewer ? 0 : p.k[i]);
  }
}
// [/listing:cost_row]

} // namespace rt::ch09
