// Chapter 11 tests of the samplers (samplers.h) against what each one promises. The bit tricks
// against the slow loops they replace (Sobol's generator matrix, the bit reversal); Owen's
// scrambling against its defining property, that a digit's flip depends on the digits above it
// alone; the Sobol' samplers' points against the definition of a (0, m, 2)-net, box by box;
// the stratified grid cell by cell; every sampler's numbers by chi-square against the uniform
// density; and the zsobol sampler's error image against white noise, by the share of its
// energy a 3 x 3 box filter keeps. Each property also meets a deliberately wrong twin that the
// same test must reject.
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "rt_catch.h"

#include "chi_square.h"
#include "convergence.h"
#include "path_cases.h"

using namespace rt;
using namespace rt::ch11;
using rt::testing::chi_square_test;
using rt::testing::ChiSquare;

namespace {

// ---- oracles for the bits -------------------------------------------------------------------

// Sobol's second dimension the slow way: the index's bits times the generator matrix, whose
// column k is the direction number v_(k+1) of the polynomial x + 1 (v_1 = 1/2, and each next
// one the last XOR itself halved).
unsigned sobol_second_by_matrix(unsigned index) {
  unsigned direction = 1u << 31, result = 0;
  for (int k = 0; k < 32; ++k) {
    if (index >> k & 1u) result ^= direction;
    direction ^= direction >> 1;
  }
  return result;
}

// Van der Corput's radical inverse the slow way: index bit k becomes the digit worth 2^-(k+1).
unsigned sobol_first_by_loop(unsigned index) {
  unsigned result = 0;
  for (int k = 0; k < 32; ++k)
    if (index >> k & 1u) result |= 1u << (31 - k);
  return result;
}

// owen_scramble's hash without its bit reversals: the multiplications then carry each bit
// towards the coarse digits, the wrong way for Owen's dependence.
unsigned scramble_unreversed(unsigned x, unsigned seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

// ---- (0, m, 2)-nets -------------------------------------------------------------------------

struct Point {
  float u, v;
};

// Whether `points` (2^m of them) put exactly one point in every elementary interval of area
// 2^-m: for each split a = 0 .. m, the 2^a x 2^(m - a) boxes of the unit square. The floats
// hold 24 bits, so floor(u * 2^a) is the box exactly. On a failure, `why` says which split.
bool is_net(const std::vector<Point>& points, std::string* why = nullptr) {
  int m = 0;
  while ((std::size_t{1} << m) < points.size()) ++m;
  if ((std::size_t{1} << m) != points.size()) {
    if (why != nullptr) *why = "not a power of two of points";
    return false;
  }
  for (const Point& p : points)
    if (!(p.u >= 0.0f && p.u < 1.0f && p.v >= 0.0f && p.v < 1.0f)) {
      if (why != nullptr) *why = "a point outside [0, 1)^2";
      return false;
    }
  for (int a = 0; a <= m; ++a) {
    std::vector<int> count(points.size(), 0);
    for (const Point& p : points) {
      const auto i = static_cast<std::size_t>(double(p.u) * double(1u << a));
      const auto j = static_cast<std::size_t>(double(p.v) * double(1u << (m - a)));
      ++count[i << (m - a) | j];
    }
    if (std::any_of(count.begin(), count.end(), [](int c) { return c != 1; })) {
      if (why != nullptr)
        *why = "the boxes of 2^-" + std::to_string(a) + " x 2^-" + std::to_string(m - a);
      return false;
    }
  }
  return true;
}

using NumberFunction =
    std::function<float(unsigned pixel, unsigned sample, unsigned vertex, unsigned dimension)>;

// A pad: a vertex and its dimensions 2k, 2k + 1.
struct Pad {
  unsigned vertex, dimension;
};
constexpr Pad k_pads[] = {{0, 0}, {0, 2}, {1, 0}, {1, 4}, {3, 6}, {7, 2}};

std::vector<Point> pad_points(const NumberFunction& number, unsigned pixel, Pad pad,
                              unsigned first, unsigned count) {
  std::vector<Point> points;
  for (unsigned s = first; s < first + count; ++s)
    points.push_back({number(pixel, s, pad.vertex, pad.dimension),
                      number(pixel, s, pad.vertex, pad.dimension + 1)});
  return points;
}

NumberFunction number_of(const Sampler& sampler) {
  return [sampler](unsigned pixel, unsigned sample, unsigned vertex, unsigned dimension) {
    return sample_number(sampler, pixel, sample, vertex, dimension);
  };
}

// The sobol sampler with its index shuffled the other way round: Owen scrambling of the
// reversed index, reversed back, lets the index's high bits decide its low ones, so the first
// 2^m samples are no longer one aligned run of Sobol' points.
float sobol_shuffled_backwards(unsigned pixel, unsigned sample, unsigned vertex,
                               unsigned dimension) {
  const unsigned pad = vertex * k_pads_per_vertex + dimension / 2, axis = dimension & 1u;
  const unsigned seed = hash_words(pixel, pad);
  const unsigned index = reverse_bits(owen_scramble(reverse_bits(sample), pcg_hash(seed)));
  const unsigned bits = axis == 0 ? sobol_first(index) : sobol_second(index);
  return unit_float(owen_scramble(bits, hash_words(seed, axis + 1)));
}

// The sobol sampler with its index hashed: Sobol' points picked at random.
float sobol_hashed_index(unsigned pixel, unsigned sample, unsigned vertex, unsigned dimension) {
  const unsigned pad = vertex * k_pads_per_vertex + dimension / 2, axis = dimension & 1u;
  const unsigned seed = hash_words(pixel, pad);
  const unsigned index = pcg_hash(sample ^ seed);
  const unsigned bits = axis == 0 ? sobol_first(index) : sobol_second(index);
  return unit_float(owen_scramble(bits, hash_words(seed, axis + 1)));
}

// How many of the powers m = 1 .. 10 the first 2^m samples of a pixel's pad, and the next
// 2^m, are both nets for.
int net_powers(const NumberFunction& number, unsigned pixel, Pad pad, std::string* why) {
  int nets = 0;
  for (unsigned m = 1; m <= 10; ++m)
    nets += is_net(pad_points(number, pixel, pad, 0, 1u << m), why) &&
            is_net(pad_points(number, pixel, pad, 1u << m, 1u << m), why);
  return nets;
}

// ---- uniformity -----------------------------------------------------------------------------

// Every correct sampler's chi-square tests together fail with probability k_alpha.
constexpr double k_alpha = 0.01;
constexpr int k_bins_1d = 64;
constexpr int k_bins_2d = 16; // per side
constexpr int k_uniformity_tests =
    4 * std::size(k_pads) * 3; // samplers x pads x (u, v, (u, v))
const double k_level = rt::testing::corrected_significance(k_alpha, k_uniformity_tests);

ChiSquare uniform_fit_1d(const std::vector<float>& numbers) {
  std::vector<double> observed(k_bins_1d + 1, 0.0); // and one for numbers outside [0, 1)
  for (const float u : numbers)
    observed[u >= 0.0f && u < 1.0f ? std::size_t(double(u) * k_bins_1d) : k_bins_1d] += 1.0;
  std::vector<double> expected(k_bins_1d, double(numbers.size()) / k_bins_1d);
  expected.push_back(0.0);
  return chi_square_test(observed, expected);
}

ChiSquare uniform_fit_2d(const std::vector<float>& us, const std::vector<float>& vs) {
  constexpr int cells = k_bins_2d * k_bins_2d;
  std::vector<double> observed(cells + 1, 0.0);
  for (std::size_t i = 0; i < us.size(); ++i) {
    const bool inside = us[i] >= 0.0f && us[i] < 1.0f && vs[i] >= 0.0f && vs[i] < 1.0f;
    observed[inside ? std::size_t(double(us[i]) * k_bins_2d) * k_bins_2d +
                          std::size_t(double(vs[i]) * k_bins_2d)
                    : std::size_t{cells}] += 1.0;
  }
  std::vector<double> expected(cells, double(us.size()) / cells);
  expected.push_back(0.0);
  return chi_square_test(observed, expected);
}

void report(const char* what, const ChiSquare& r, double level = k_level) {
  UNSCOPED_INFO(what << ": chi-square " << r.statistic << " on " << r.degrees_of_freedom
                     << " degrees of freedom, p = " << r.p_value << "; the level is " << level);
}

} // namespace

// ---- the bits -------------------------------------------------------------------------------

TEST_CASE("samplers: Sobol's two dimensions equal the generator matrix and the bit reversal",
          "[ch11][samplers]") {
  std::vector<unsigned> indices;
  for (unsigned i = 0; i < 70000; ++i) indices.push_back(i);
  for (unsigned i = 0; i < 70000; ++i) indices.push_back(pcg_hash(i));
  for (const unsigned extreme : {0x7fffffffu, 0x80000000u, 0xfffffffeu, 0xffffffffu})
    indices.push_back(extreme);
  int second_wrong = 0, first_wrong = 0;
  for (const unsigned i : indices) {
    second_wrong += sobol_second(i) != sobol_second_by_matrix(i);
    first_wrong += sobol_first(i) != sobol_first_by_loop(i);
  }
  CHECK(second_wrong == 0);
  CHECK(first_wrong == 0);
  CHECK(reverse_bits(1u) == 0x80000000u);
  CHECK(reverse_bits(0x0000f00du) == 0xb00f0000u);
  // The matrix's first columns, written out: Pascal's triangle mod 2, read from the top.
  CHECK(sobol_second(1) == 0x80000000u);
  CHECK(sobol_second(2) == 0xc0000000u);
  CHECK(sobol_second(3) == 0x40000000u);
  CHECK(sobol_second(4) == 0xa0000000u);
}

TEST_CASE("samplers: Owen scrambling is a bijection whose flips depend on the digits above "
          "alone, and without the bit reversals it is not Owen's",
          "[ch11][samplers]") {
  for (const unsigned seed : {0u, 1u, 0x9e3779b9u, 0xffffffffu, pcg_hash(7)}) {
    CAPTURE(seed);
    // No two of 2^20 distinct inputs (counting up, and scattered by pcg_hash, itself a
    // bijection) meet.
    for (const bool scattered : {false, true}) {
      std::vector<unsigned> outputs;
      for (unsigned i = 0; i < (1u << 20); ++i)
        outputs.push_back(owen_scramble(scattered ? pcg_hash(i) : i, seed));
      std::sort(outputs.begin(), outputs.end());
      CHECK(std::adjacent_find(outputs.begin(), outputs.end()) == outputs.end());
    }
    // The top 16 bits of the output are a function of the top 16 of the input, whatever the
    // bits below, and a permutation of all 2^16 prefixes.
    std::vector<char> seen(1u << 16, 0);
    int repeated = 0, below_matters = 0;
    for (unsigned prefix = 0; prefix < (1u << 16); ++prefix) {
      const unsigned top = owen_scramble(prefix << 16, seed) >> 16;
      below_matters +=
          (owen_scramble(prefix << 16 | (pcg_hash(prefix) & 0xffffu), seed) >> 16) != top;
      repeated += seen[top]++ != 0;
    }
    CHECK(repeated == 0);
    CHECK(below_matters == 0);
  }
  // Owen's property, digit by digit: flipping input bit j (worth 2^-(32-j)) leaves every more
  // significant output bit alone and flips output bit j itself.
  int violations = 0, unreversed_violations = 0;
  for (unsigned k = 0; k < 2000; ++k) {
    const unsigned x = pcg_hash(k), seed = pcg_hash(k + 1000000u);
    for (unsigned j = 0; j < 32; ++j) {
      const unsigned change = owen_scramble(x, seed) ^ owen_scramble(x ^ (1u << j), seed);
      violations += (change >> j) != 1u;
      const unsigned wrong =
          scramble_unreversed(x, seed) ^ scramble_unreversed(x ^ (1u << j), seed);
      unreversed_violations += (wrong >> j) != 1u;
    }
  }
  CHECK(violations == 0);
  CHECK(unreversed_violations > 2000 * 16); // nearly every bit below the top fails
}

TEST_CASE("samplers: the independent sampler is chapter 11's hash, number for number",
          "[ch11][samplers]") {
  const Sampler made = make_sampler(SamplerKind::independent, {64, 48}, 16);
  int different = 0;
  for (unsigned k = 0; k < 20000; ++k) {
    const unsigned pixel = k < 10000 ? k : pcg_hash(k), sample = k % 37 + (k >> 9) * 1000003u;
    const unsigned vertex = k % 11, dimension = (k / 11) % k_dimensions;
    const float hash = sample_number(pixel, sample, vertex, dimension);
    different += sample_number(Sampler{}, pixel, sample, vertex, dimension) != hash;
    different += sample_number(made, pixel, sample, vertex, dimension) != hash;
  }
  CHECK(different == 0);
}

TEST_CASE("samplers: sample_pair draws the two numbers sample_number draws one at a time",
          "[ch11][samplers]") {
  int different = 0;
  for (const SamplerKind kind : k_samplers) {
    const Sampler sampler = make_sampler(kind, {37, 23}, 9);
    for (unsigned k = 0; k < 5000; ++k) {
      const unsigned pixel = k % (37 * 23), sample = k / 7 + (k % 3) * 1000u;
      const unsigned vertex = k % 5, first = 2 * (k % k_pads_per_vertex);
      const Vec2f pair = sample_pair(sampler, pixel, sample, vertex, first);
      different += pair.x != sample_number(sampler, pixel, sample, vertex, first);
      different += pair.y != sample_number(sampler, pixel, sample, vertex, first + 1);
    }
  }
  CHECK(different == 0);
}

// ---- nets -----------------------------------------------------------------------------------

TEST_CASE("samplers: sobol's first 2^m samples and the next 2^m are (0, m, 2)-nets in every "
          "pad, and a wrongly shuffled index is not",
          "[ch11][samplers]") {
  const NumberFunction sobol = number_of(make_sampler(SamplerKind::sobol, {64, 48}, 16));
  for (const unsigned pixel : {0u, 1u, 777u, 3071u, 0xfffffu}) {
    for (const Pad pad : k_pads) {
      CAPTURE(pixel, pad.vertex, pad.dimension);
      std::string why;
      const bool one_point = is_net(pad_points(sobol, pixel, pad, 0, 1), &why); // m = 0
      const int nets = net_powers(sobol, pixel, pad, &why);
      CAPTURE(why);
      CHECK(one_point);
      CHECK(nets == 10);
      // The wrong twins keep every point uniform but lose the nets, at once or soon.
      CHECK(net_powers(sobol_shuffled_backwards, pixel, pad, nullptr) <= 2);
      CHECK(net_powers(sobol_hashed_index, pixel, pad, nullptr) <= 2);
    }
  }
  // Two pixels, two pads, draw different nets.
  const auto first = pad_points(sobol, 5, k_pads[0], 0, 16);
  const auto other_pixel = pad_points(sobol, 6, k_pads[0], 0, 16);
  const auto other_pad = pad_points(sobol, 5, k_pads[1], 0, 16);
  CHECK(first[3].u != other_pixel[3].u);
  CHECK(first[3].u != other_pad[3].u);
}

TEST_CASE("samplers: zsobol's pixels, every aligned square of pixels and the whole image are "
          "nets, and each pixel's samples have indices of their own",
          "[ch11][samplers]") {
  struct Case {
    Extent extent;
    int samples;
  };
  const Case cases[] = {{{16, 16}, 4},  // an even log2 of the samples per pixel, one tile
                        {{8, 8}, 8},    // an odd one: a binary digit left at the bottom
                        {{5, 3}, 16},   // an image inside a square of 8 x 8
                        {{1, 1}, 32},   // one pixel: the sequence itself
                        {{4, 4}, 5},    // 5 samples: nets of 8
                        {{64, 64}, 4},  // 4 x 4 tiles of 16 x 16 pixels, their number scrambled
                        {{40, 24}, 2}}; // tiles, some cut off by the image's edge
  for (const Case& c : cases) {
    const Sampler sampler = make_sampler(SamplerKind::zsobol, c.extent, c.samples);
    const NumberFunction number = number_of(sampler);
    const unsigned block = 1u << sampler.log2_block;
    const auto width = unsigned(c.extent.width), height = unsigned(c.extent.height);
    CAPTURE(width, height, c.samples);
    REQUIRE(block >= unsigned(c.samples));
    REQUIRE(block < 2u * unsigned(c.samples));
    for (const Pad pad : k_pads) {
      CAPTURE(pad.vertex, pad.dimension);
      // Every pixel's block of samples, and its next block (a new net of its own).
      int pixel_nets = 0;
      for (unsigned p = 0; p < width * height; ++p)
        pixel_nets += is_net(pad_points(number, p, pad, 0, block)) &&
                      is_net(pad_points(number, p, pad, block, block));
      CHECK(pixel_nets == int(width * height));
      // Every aligned square of 2^k x 2^k pixels inside the image: the 2 x 2 quads, the
      // 16 x 16 tiles, the whole image when it is a square of a power of two.
      for (unsigned k = 1; k <= sampler.log2_resolution; ++k) {
        const unsigned side = 1u << k;
        int squares = 0, nets = 0;
        std::string why;
        for (unsigned y0 = 0; y0 + side <= height; y0 += side)
          for (unsigned x0 = 0; x0 + side <= width; x0 += side) {
            std::vector<Point> points;
            for (unsigned y = y0; y < y0 + side; ++y)
              for (unsigned x = x0; x < x0 + side; ++x) {
                const auto own = pad_points(number, y * width + x, pad, 0, block);
                points.insert(points.end(), own.begin(), own.end());
              }
            ++squares;
            nets += is_net(points, &why);
          }
        CAPTURE(side, why);
        CHECK(nets == squares);
      }
    }
    // (pixel, sample in block) -> Sobol' index: one to one, inside the image's run.
    const unsigned bits = 2 * sampler.log2_resolution + sampler.log2_block;
    for (const unsigned seed : {0u, 12345u, pcg_hash(99)}) {
      std::vector<unsigned> indices;
      bool inside = true;
      for (unsigned p = 0; p < width * height; ++p)
        for (unsigned s = 0; s < block; ++s) {
          const unsigned index = zsobol_index(sampler, p, s, seed);
          indices.push_back(index);
          inside = inside && (bits >= 32 || index < (1u << bits));
        }
      std::sort(indices.begin(), indices.end());
      CHECK(std::adjacent_find(indices.begin(), indices.end()) == indices.end());
      CHECK(inside);
    }
  }
}

TEST_CASE("samplers: zsobol's index fits 32 bits at every image size", "[ch11][samplers]") {
  for (const Extent extent : {Extent{1, 1}, Extent{7, 1}, Extent{1920, 1080}, Extent{1, 4096},
                              Extent{16384, 16384}, Extent{65536, 2}})
    for (const int samples : {0, 1, 3, 64, 1 << 20, INT_MAX}) {
      CAPTURE(extent.width, extent.height, samples);
      const Sampler s = make_sampler(SamplerKind::zsobol, extent, samples);
      CHECK((1u << s.log2_resolution) >= unsigned(std::max(extent.width, extent.height)));
      CHECK(2 * s.log2_resolution + s.log2_block <= 32);
      CHECK(s.log2_block < 32);
      CHECK(s.width == unsigned(extent.width));
    }
  // 0 samples: a net of 16.
  CHECK(make_sampler(SamplerKind::zsobol, {8, 8}, 0).log2_block == 4);
  CHECK(make_sampler(SamplerKind::stratified, {8, 8}, 0).block == 16);
}

TEST_CASE("samplers: Morton codes interleave x and y, and the 24 digit permutations are all "
          "different",
          "[ch11][samplers]") {
  for (unsigned y = 0; y < 64; ++y)
    for (unsigned x = 0; x < 64; ++x) {
      unsigned expected = 0;
      for (int b = 0; b < 16; ++b)
        expected |= (x >> b & 1u) << (2 * b) | (y >> b & 1u) << (2 * b + 1);
      CHECK(morton_code(x, y) == expected);
    }
  CHECK(morton_code(0xffffu, 0) == 0x55555555u);
  CHECK(morton_code(0, 0xffffu) == 0xaaaaaaaau);
  std::set<std::array<unsigned, 4>> permutations;
  for (unsigned k = 0; k < 24; ++k) {
    std::array<unsigned, 4> image{};
    std::array<bool, 4> hit{};
    for (unsigned d = 0; d < 4; ++d) {
      image[d] = permute_digit(d, k);
      REQUIRE(image[d] < 4);
      hit[image[d]] = true;
    }
    CHECK(std::all_of(hit.begin(), hit.end(), [](bool h) { return h; })); // a permutation
    permutations.insert(image);
  }
  CHECK(permutations.size() == 24);
}

// ---- stratified -----------------------------------------------------------------------------

TEST_CASE("samplers: permute_index is a permutation of 0 .. n - 1", "[ch11][samplers]") {
  int permutations = 0;
  for (unsigned n = 1; n <= 300; ++n)
    for (const unsigned seed : {0u, 1u, 2u, 0x12345678u, 0xffffffffu, pcg_hash(n)}) {
      std::vector<char> hit(n, 0);
      int outside = 0, repeated = 0;
      for (unsigned i = 0; i < n; ++i) {
        const unsigned j = permute_index(i, n, seed);
        if (j >= n)
          ++outside;
        else
          repeated += hit[j]++ != 0;
      }
      if (outside == 0 && repeated == 0) {
        ++permutations;
      } else {
        CAPTURE(n, seed);
        CHECK(outside == 0);
        CHECK(repeated == 0);
      }
    }
  CHECK(permutations == 300 * 6);
}

namespace {

// Where permute_index sends `position`, over k_seeds seeds (consecutive, or scattered by
// pcg_hash), against the uniform law on 0 .. n - 1; and the identity, which a test of a
// permutation chosen at random must reject.
constexpr int k_seeds = 40000;
void check_position_uniform(unsigned n, unsigned position, bool scattered, double level) {
  CAPTURE(n, position, scattered);
  std::vector<double> observed(n, 0.0), identity(n, 0.0);
  for (unsigned k = 0; k < unsigned(k_seeds); ++k) {
    observed[permute_index(position, n, scattered ? pcg_hash(k) : k)] += 1.0;
    identity[position] += 1.0;
  }
  const std::vector<double> expected(n, double(k_seeds) / n);
  const ChiSquare r = chi_square_test(observed, expected);
  report("permute_index", r, level);
  CHECK(r.p_value > level);
  CHECK(chi_square_test(identity, expected).p_value < level);
}

} // namespace

TEST_CASE("samplers: permute_index sends each position anywhere with equal odds, n a power "
          "of two",
          "[ch11][samplers]") {
  const double level = rt::testing::corrected_significance(k_alpha, 4 * 2 * 2);
  for (const unsigned n : {2u, 4u, 16u, 128u})
    for (const unsigned position : {0u, n - 1})
      for (const bool scattered : {false, true})
        check_position_uniform(n, position, scattered, level);
}

// For n other than a power of two, permute_index walks the cycle of a bijection of the next
// power of two until it comes back into 0 .. n - 1. The walk alone does not keep the odds
// equal: without its final random turn, over a million seeds permute_index(0, 3, seed) is 1
// half the time, and 0 and 2 a quarter each; for n = 9, 3 and 4 come out 13% of the time where
// 11.1% is due, and the first sample of a stratified block of 9 lands in the grid's middle row
// (v between 1/3 and 2/3) 37% of the time, not 33%: an image whose pixels stop in the middle
// of a block (the window, or a progressive render) would be biased.
TEST_CASE("samplers: permute_index sends each position anywhere with equal odds, n not a "
          "power of two, and so does a stratified block's first sample",
          "[ch11][samplers]") {
  const double level = rt::testing::corrected_significance(k_alpha, 4 * 2 * 2 + 1);
  for (const unsigned n : {3u, 7u, 9u, 100u})
    for (const unsigned position : {0u, n - 1})
      for (const bool scattered : {false, true})
        check_position_uniform(n, position, scattered, level);
  // Sample 0 of every pixel of a 256 x 256 image, stratified in blocks of 9: its cell of the
  // 3 x 3 grid.
  const Sampler sampler = make_sampler(SamplerKind::stratified, {256, 256}, 9);
  std::vector<double> observed(9, 0.0);
  for (unsigned pixel = 0; pixel < 256u * 256u; ++pixel) {
    const float u = sample_number(sampler, pixel, 0, 1, 0);
    const float v = sample_number(sampler, pixel, 0, 1, 1);
    observed[std::size_t(double(u) * 3.0) * 3 + std::size_t(double(v) * 3.0)] += 1.0;
  }
  const ChiSquare r = chi_square_test(observed, std::vector<double>(9, 256.0 * 256.0 / 9.0));
  report("stratified, the first sample of a block of 9", r, level);
  CHECK(r.p_value > level);
}

TEST_CASE("samplers: stratified puts one sample in each cell of its grid in every block, and "
          "every number from 0 up to 1",
          "[ch11][samplers]") {
  for (const int n : {1, 2, 4, 9, 10, 16, 64}) {
    const Sampler sampler = make_sampler(SamplerKind::stratified, {64, 48}, n);
    const unsigned cells = sampler.cells;
    CAPTURE(n);
    REQUIRE(sampler.block == unsigned(n));
    REQUIRE(cells * cells <= unsigned(n));
    REQUIRE((cells + 1) * (cells + 1) > unsigned(n));
    for (const unsigned pixel : {0u, 13u, 3071u})
      for (const Pad pad : k_pads)
        for (const unsigned block : {0u, 1u, 5u, 1000u}) {
          std::vector<int> count(cells * cells, 0);
          bool inside = true;
          for (unsigned j = 0; j < unsigned(n); ++j) {
            const unsigned sample = block * unsigned(n) + j;
            const float u = sample_number(sampler, pixel, sample, pad.vertex, pad.dimension);
            const float v =
                sample_number(sampler, pixel, sample, pad.vertex, pad.dimension + 1);
            inside = inside && u >= 0.0f && u < 1.0f && v >= 0.0f && v < 1.0f;
            if (j < cells * cells && inside)
              ++count[std::size_t(double(u) * cells) * cells + std::size_t(double(v) * cells)];
          }
          if (!inside ||
              std::any_of(count.begin(), count.end(), [](int c) { return c != 1; })) {
            CAPTURE(pixel, pad.vertex, pad.dimension, block);
            CHECK(inside);
            CHECK(std::all_of(count.begin(), count.end(), [](int c) { return c == 1; }));
          }
        }
  }
  // Every sampler, every pixel of a small image, many samples, every vertex and dimension: in
  // [0, 1), also for a grid of 46340^2 cells (the most an int of samples allows).
  int outside = 0;
  long long numbers = 0;
  for (const SamplerKind kind : k_samplers)
    for (const int n : {1, 3, 8, 17, INT_MAX}) {
      const Sampler sampler = make_sampler(kind, {5, 3}, n);
      for (unsigned pixel = 0; pixel < 15; ++pixel)
        for (const unsigned sample :
             {0u, 1u, 2u, 7u, 16u, 33u, 1000u, 0x7ffffffeu, 0x80000000u, 0xffffffffu})
          for (unsigned vertex = 0; vertex < 8; ++vertex)
            for (unsigned dimension = 0; dimension < k_dimensions; ++dimension) {
              const float u = sample_number(sampler, pixel, sample, vertex, dimension);
              outside += !(u >= 0.0f && u < 1.0f);
              ++numbers;
            }
    }
  CHECK(outside == 0);
  CHECK(numbers == 4 * 5 * 15 * 10 * 8 * k_dimensions);
  CHECK(unit_float(0xffffffffu) < 1.0f);
  CHECK(unit_float(0u) == 0.0f);
}

// ---- uniformity -----------------------------------------------------------------------------

TEST_CASE("samplers: every sampler's numbers are uniform, each dimension and each pad, and a "
          "squared number or a missing stratum is rejected",
          "[ch11][samplers]") {
  // Pearson's test counts independent draws, and a pixel's own samples are deliberately not:
  // they share a net, and below the net's resolution owen_scramble's hash flips the digits of
  // a pixel's points with related coins, so that their counts in fine bins move together (the
  // sobol sampler's 16 samples of each of 64 x 64 pixels, in 64 bins, give statistics from
  // about 10 to above 120 on 63 degrees of freedom; a scramble with an independent coin per
  // digit and prefix, 27 to 73). So each pixel gives one sample, pixel p its sample p mod 16:
  // every sample index is tested, and the per-pixel samplers' draws are independent. The zsobol
  // sampler's pixels share one net, which only evens the counts out.
  const Extent extent{256, 256};
  const int spp = 16;
  for (const SamplerKind kind : k_samplers) {
    const Sampler sampler = make_sampler(kind, extent, spp);
    CAPTURE(to_string(kind));
    for (const Pad pad : k_pads) {
      CAPTURE(pad.vertex, pad.dimension);
      std::vector<float> us, vs;
      for (unsigned pixel = 0; pixel < unsigned(extent.pixel_count()); ++pixel) {
        const unsigned s = pixel % unsigned(spp);
        us.push_back(sample_number(sampler, pixel, s, pad.vertex, pad.dimension));
        vs.push_back(sample_number(sampler, pixel, s, pad.vertex, pad.dimension + 1));
      }
      const ChiSquare u = uniform_fit_1d(us), v = uniform_fit_1d(vs);
      const ChiSquare uv = uniform_fit_2d(us, vs);
      report("u", u);
      report("v", v);
      report("(u, v)", uv);
      CHECK(u.p_value > k_level);
      CHECK(v.p_value > k_level);
      CHECK(uv.p_value > k_level);
      // The wrong twins: u * u, and the stratum [0, 1/8) moved onto [1/8, 1/4).
      std::vector<float> squared = us, dropped = us;
      for (float& x : squared) x = x * x;
      for (float& x : dropped)
        if (x < 0.125f) x += 0.125f;
      CHECK(uniform_fit_1d(squared).p_value < k_level);
      CHECK(uniform_fit_2d(squared, vs).p_value < k_level);
      CHECK(uniform_fit_1d(dropped).p_value < k_level);
      CHECK(uniform_fit_2d(dropped, vs).p_value < k_level);
    }
  }
}

// ---- blue noise -----------------------------------------------------------------------------

namespace {

// An image's error as lowpass_share reads it: each pixel's estimate of the integral of f over
// the unit square from `spp` samples of the bounce's pair (vertex 1, dimensions 0 and 1),
// against the exact value, as grey.
double pixel_error_lowpass(const Sampler& sampler, Extent extent, int spp,
                           const std::function<double(double, double)>& f, double exact) {
  std::vector<Vec3f> image;
  for (unsigned pixel = 0; pixel < unsigned(extent.pixel_count()); ++pixel) {
    double sum = 0.0;
    for (unsigned s = 0; s < unsigned(spp); ++s)
      sum += f(sample_number(sampler, pixel, s, 1, 0), sample_number(sampler, pixel, s, 1, 1));
    const auto mean = float(sum / spp);
    image.push_back({mean, mean, mean});
  }
  const std::vector<double> reference(image.size() * 3, exact);
  return lowpass_share(image, reference, extent);
}

} // namespace

TEST_CASE("samplers: lowpass_share is 1/9 for white noise, 1/81 for a checkerboard, 1 for a "
          "constant error",
          "[ch11][samplers]") {
  const Extent extent{128, 96};
  const std::size_t pixels = std::size_t(extent.pixel_count());
  const std::vector<double> zero(pixels * 3, 0.0);
  std::vector<Vec3f> white, checker, constant;
  for (std::size_t i = 0; i < pixels; ++i) {
    const float e = float(pcg_hash(unsigned(i)) >> 8) / 16777216.0f - 0.5f;
    white.push_back({e, e, e});
    const int x = int(i) % extent.width, y = int(i) / extent.width;
    const float sign = (x + y) % 2 == 0 ? 0.25f : -0.25f;
    checker.push_back({sign, sign, sign});
    constant.push_back({0.1f, 0.1f, 0.1f});
  }
  // Independent errors: the box's mean of nine has a ninth of the variance, up to the noise
  // of 12,000 pixels (a few percent).
  CHECK(lowpass_share(white, zero, extent) == Approx(1.0 / 9.0).epsilon(0.06));
  // Every 3 x 3 box of a checkerboard holds five of one sign and four of the other: its mean
  // is e / 9, so a share of 1/81 exactly.
  CHECK(lowpass_share(checker, zero, extent) == Approx(1.0 / 81.0).epsilon(1e-9));
  CHECK(lowpass_share(constant, zero, extent) == Approx(1.0).epsilon(1e-6));
}

TEST_CASE("samplers: zsobol spreads a pixel integral's error as blue noise, the per-pixel "
          "samplers as white noise",
          "[ch11][samplers]") {
  // Each pixel estimates the integral of sin(u) sin(v) over the unit square, (1 - cos 1)^2,
  // from 4 samples. Measured (128 x 128): about 0.11 for the three per-pixel samplers, 0.05
  // for zsobol, whose aligned 2 x 2 quads' mean errors have a sixth of the variance, or less,
  // of four independent pixels'. A discontinuous integrand (the indicator of u + v < 1) gains
  // less: along a diagonal edge a net of 16 points does not do much better than four of 4.
  const Extent extent{128, 128};
  const int spp = 4;
  const auto f = [](double u, double v) { return std::sin(u) * std::sin(v); };
  const double exact = (1.0 - std::cos(1.0)) * (1.0 - std::cos(1.0));
  double share[4] = {};
  for (const SamplerKind kind : k_samplers)
    share[int(kind)] =
        pixel_error_lowpass(make_sampler(kind, extent, spp), extent, spp, f, exact);
  CAPTURE(share[0], share[1], share[2], share[3]);
  CHECK(share[int(SamplerKind::independent)] == Approx(1.0 / 9.0).epsilon(0.1));
  CHECK(share[int(SamplerKind::stratified)] == Approx(1.0 / 9.0).epsilon(0.1));
  CHECK(share[int(SamplerKind::sobol)] == Approx(1.0 / 9.0).epsilon(0.1));
  CHECK(share[int(SamplerKind::zsobol)] < 0.6 * share[int(SamplerKind::independent)]);
}
