// Pearson's chi-square test and the chi-square law's upper tail. See chi_square.h.
#include "chi_square.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace rt::testing {

namespace {

// P(a, x), the regularised lower incomplete gamma function, by its power series
// x^a e^-x / Gamma(a + 1) * sum_n x^n / ((a + 1) ... (a + n)): quick where x < a + 1.
double lower_gamma_series(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 10000 && std::abs(term) > std::abs(sum) * 1e-16; ++n) {
    term *= x / (a + n);
    sum += term;
  }
  return sum * std::exp(a * std::log(x) - x - std::lgamma(a));
}

// Q(a, x) = 1 - P(a, x) by its continued fraction, evaluated with the modified Lentz method:
// quick where x >= a + 1, and it keeps the tail's relative accuracy where Q is tiny.
double upper_gamma_fraction(double a, double x) {
  constexpr double k_tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / k_tiny, d = 1.0 / b, h = d;
  for (int n = 1; n < 10000; ++n) {
    const double an = -n * (n - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < k_tiny) d = k_tiny;
    c = b + an / c;
    if (std::abs(c) < k_tiny) c = k_tiny;
    d = 1.0 / d;
    const double step = d * c;
    h *= step;
    if (std::abs(step - 1.0) < 1e-16) break;
  }
  return std::exp(a * std::log(x) - x - std::lgamma(a)) * h;
}

} // namespace

double chi_square_upper_tail(double statistic, int degrees_of_freedom) {
  if (degrees_of_freedom <= 0) throw std::invalid_argument("chi-square: no degrees of freedom");
  if (!(statistic > 0.0)) return 1.0;
  const double a = 0.5 * degrees_of_freedom, x = 0.5 * statistic;
  return x < a + 1.0 ? 1.0 - lower_gamma_series(a, x) : upper_gamma_fraction(a, x);
}

double corrected_significance(double alpha, int tests) {
  return 1.0 - std::pow(1.0 - alpha, 1.0 / tests);
}

ChiSquare chi_square_test(std::span<const double> observed, std::span<const double> expected,
                          double min_expected) {
  if (observed.size() != expected.size())
    throw std::invalid_argument("chi-square: observed and expected differ in length");
  ChiSquare result;
  std::vector<std::size_t> order(expected.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });
  std::vector<double> pooled_observed, pooled_expected;
  double pool_observed = 0.0, pool_expected = 0.0;
  for (const std::size_t cell : order) {
    if (expected[cell] <= 0.0) {
      result.stray += observed[cell];
      continue;
    }
    pool_observed += observed[cell];
    pool_expected += expected[cell];
    if (pool_expected >= min_expected) {
      pooled_observed.push_back(pool_observed);
      pooled_expected.push_back(pool_expected);
      pool_observed = pool_expected = 0.0;
    }
  }
  if (pool_expected > 0.0) {
    if (pooled_expected.empty()) {
      pooled_observed.push_back(0.0);
      pooled_expected.push_back(0.0);
    }
    pooled_observed.back() += pool_observed;
    pooled_expected.back() += pool_expected;
  }
  for (std::size_t k = 0; k < pooled_expected.size(); ++k) {
    const double difference = pooled_observed[k] - pooled_expected[k];
    result.statistic += difference * difference / pooled_expected[k];
  }
  result.degrees_of_freedom = static_cast<int>(pooled_expected.size()) - 1;
  if (result.stray > 0.0 || result.degrees_of_freedom < 1)
    result.p_value = 0.0;
  else
    result.p_value = chi_square_upper_tail(result.statistic, result.degrees_of_freedom);
  return result;
}

} // namespace rt::testing
