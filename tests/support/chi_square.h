// Pearson's chi-square goodness-of-fit test, which renderers run on every sampler (pbrt-v4's
// sampling tests, Mitsuba 3's chi2 module): draw many samples, count them in cells, integrate
// the sampler's density over each cell for the counts it promises, and ask how likely a
// difference as large as the one seen would be if the density were right.
#pragma once

#include <span>

namespace rt::testing {

struct ChiSquare {
  double statistic = 0.0;     // the sum over cells of (observed - expected)^2 / expected
  int degrees_of_freedom = 0; // the cells left after merging, less one
  double p_value = 1.0;       // P(a statistic this large | the density is right); 0 if stray
  double stray = 0.0;         // samples seen in cells where the density promises none
};

// The test of `observed` counts against `expected` ones, cell by cell. Cells that expect fewer
// than `min_expected` samples are pooled, smallest first, until each pool expects at least
// that many (the statistic follows the chi-square law only when every cell expects a few);
// a pool left short at the end joins the last full one. A sample in a cell that expects none
// at all (a direction below the surface, a point off the triangle) fails the test outright.
ChiSquare chi_square_test(std::span<const double> observed, std::span<const double> expected,
                          double min_expected = 5.0);

// P(X >= statistic) for X chi-square distributed with `degrees_of_freedom`: the regularised
// upper incomplete gamma function Q(k / 2, statistic / 2).
double chi_square_upper_tail(double statistic, int degrees_of_freedom);

// The level each of `tests` independent tests must pass at so that a correct sampler fails
// any of them with probability `alpha` in all (Sidak's form of the Bonferroni correction).
double corrected_significance(double alpha, int tests);

} // namespace rt::testing
