// Vec3 and the difference of products: exact answers, and accuracy where naive code cancels.
#include <cmath>
#include <random>

#include "rt_catch.h"

#include "rt/vec.h"

using namespace rt;

TEST_CASE("Vec3 arithmetic", "[common]") {
  const Vec3d a{1, 2, 3}, b{-4, 5, 0.5};
  CHECK(a + b == Vec3d{-3, 7, 3.5});
  CHECK(a - b == Vec3d{5, -3, 2.5});
  CHECK(a * 2.0 == Vec3d{2, 4, 6});
  CHECK(2.0 * a == a * 2.0);
  CHECK(a * b == Vec3d{-4, 10, 1.5});
  CHECK(-a == Vec3d{-1, -2, -3});
  CHECK(a / 2.0 == Vec3d{0.5, 1, 1.5});
  CHECK(dot(a, b) == Approx(-4 + 10 + 1.5));
  CHECK(cross(Vec3d{1, 0, 0}, Vec3d{0, 1, 0}) == Vec3d{0, 0, 1});
  CHECK(cross(a, b) == Vec3d{2 * 0.5 - 3 * 5, 3 * -4 - 1 * 0.5, 1 * 5 - 2 * -4});
  CHECK(length(Vec3d{3, 4, 12}) == 13.0);
  CHECK(length(normalize(Vec3f{0.f, 3.f, 4.f})) == Approx(1.0f));
  CHECK(elementwise_min(a, b) == Vec3d{-4, 2, 0.5});
  CHECK(elementwise_max(a, b) == Vec3d{1, 5, 3});
  CHECK(elementwise_abs(b) == Vec3d{4, 5, 0.5});
  CHECK(min_component(b) == -4);
  CHECK(max_component(b) == 5);
  CHECK(a[0] == 1);
  CHECK(a[2] == 3);
  CHECK(a.as<float>() == Vec3f{1, 2, 3});
}

TEST_CASE("cross product is perpendicular to both inputs", "[common]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  for (int i = 0; i < 1000; ++i) {
    const Vec3d a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
    const Vec3d c = cross(a, b);
    const double scale = length(a) * length(b) * length(c);
    CHECK(std::abs(dot(c, a)) <= 1e-12 * scale);
    CHECK(std::abs(dot(c, b)) <= 1e-12 * scale);
  }
}

// The exact value of a*b - c*d for float inputs: each product of two floats is exact in
// double (24 + 24 bits < 53), so only the final subtraction rounds.
static double exact_dop(float a, float b, float c, float d) {
  return double(a) * double(b) - double(c) * double(d);
}

TEST_CASE("difference_of_products stays accurate where a*b - c*d cancels", "[common]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.5f, 2.0f);
  int naive_bad = 0;
  for (int i = 0; i < 100000; ++i) {
    const float a = u(rng), b = u(rng);
    // c*d within a few ulps of a*b: the hard case for the naive formula.
    const float c = std::nextafter(a, 4.0f);
    const float d = b * (1.0f - 1e-7f * float(i % 7));
    const double exact = exact_dop(a, b, c, d);
    const float good = difference_of_products(a, b, c, d);
    const volatile float ab = a * b, cd = c * d; // volatile: keep the naive roundings
    const float naive = ab - cd;
    if (exact == 0.0) continue;
    // Kahan's bound: 1.5 ulp of the result.
    const double ulp = std::abs(double(std::nextafter(float(exact), 1e30f)) - float(exact));
    REQUIRE(std::abs(double(good) - exact) <= 1.5 * ulp);
    if (std::abs(double(naive) - exact) > 1e3 * ulp) ++naive_bad;
  }
  CHECK(naive_bad > 1000); // the naive form really does fail here
}

TEST_CASE("difference_of_products in double", "[common]") {
  const double a = 1.0 + 0x1p-30, b = 1.0 - 0x1p-30; // a*b = 1 - 2^-60
  CHECK(difference_of_products(a, b, 1.0, 1.0) == -0x1p-60);
  CHECK(a * b - 1.0 == 0.0); // the naive form loses it entirely
}
