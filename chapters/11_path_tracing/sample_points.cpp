// Chapter 11, second part: the samplers' points, written out to be looked at. For one pixel,
// one path vertex and one pad (two dimensions), the points (u, v) that samples 0, 1, 2, ... of
// a sampler draw there, by samplers.h's own sample_number: the book's pictures of clumps and
// gaps, grids and nets are drawn from these files, not from a copy of the formulas. With
// --image, sample 0 of every pixel of the image instead: what the zsobol sampler spreads over
// the whole image, and --order adds the index of each pixel in its image-wide sequence.
//
//   ch11_sample_points [--sampler NAME] [--count N] [--pixel P] [--vertex V] [--dimension D]
//                      [--width W] [--height H] [--image [--order FILE.csv]]
//                      [--output FILE.csv]
#include <bit>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>

#include "path_render.h"
#include "rt/cli.h"
#include "rt/error.h"
#include "rt/output_file.h"
#include "samplers.h"

namespace {

using namespace rt;
using namespace rt::ch11;

// More rows than anyone would plot: a million points is 30 MB of text.
constexpr long long k_max_points = 1LL << 20;

struct Options {
  std::string sampler = "sobol";
  int count = 16;    // samples per pixel: the points written, and what the sampler is made for
  int pixel = 0;     // whose samples
  int vertex = 0;    // 0: the camera's point in its pixel; k: the k-th surface of the path
  int dimension = 0; // the pad's first dimension at that vertex (even)
  int width = 8, height = 8;
  bool image = false; // sample 0 of every pixel, instead of one pixel's samples
  std::string order;  // with --image and zsobol: each pixel's index in the image-wide sequence
  std::string output = "ch11_sample_points.csv";
};

// Everything the run would refuse, before any file is touched: one line each.
void check(const Options& o, const CLI::App& app) {
  const long long pixels = Extent{o.width, o.height}.pixel_count();
  if (o.dimension % 2 != 0)
    throw UsageError("--dimension " + std::to_string(o.dimension) +
                     ": a pad starts at an even dimension (0, 2, 4 or 6); its two numbers are "
                     "one point");
  if (o.image && app.count("--pixel") > 0)
    throw UsageError("--image writes sample 0 of every pixel: not with --pixel");
  if (!o.image && o.pixel >= pixels)
    throw UsageError("--pixel " + std::to_string(o.pixel) + " is outside the " +
                     std::to_string(o.width) + "x" + std::to_string(o.height) + " image (" +
                     std::to_string(pixels) + " pixels)");
  if (o.image && pixels > k_max_points)
    throw UsageError("--image with " + std::to_string(pixels) + " pixels: at most " +
                     std::to_string(k_max_points) + " points are written");
  if (!o.order.empty() && !(o.image && parse_sampler(o.sampler) == SamplerKind::zsobol))
    throw UsageError("--order is the zsobol sampler's image-wide order: it needs --image and "
                     "--sampler zsobol");
  for (const std::string* path : {&o.output, &o.order})
    if (!path->empty() && !path->ends_with(".csv"))
      throw UsageError("output '" + *path + "': expected a .csv file name");
}

// The zsobol sampler's index of (pixel, sample 0) in the image-wide Sobol' sequence, by
// zsobol_index with the seed zsobol_pair gives it for block 0.
unsigned zsobol_index_of(const Sampler& s, unsigned pixel, unsigned pad) {
  return zsobol_index(s, pixel, 0u, hash_words(pad, 0u, 0x5bd1e995u));
}

// How many leading binary digits two 32-bit fractions share (32 when they are equal).
int shared_digits(unsigned a, unsigned b) { return a == b ? 32 : std::countl_zero(a ^ b); }

// Holds the order to the sampler's own points, so that this file cannot quietly draw another
// order. Owen's scrambling, whatever its seeds, keeps how many leading digits two points
// share: so the points that pixels p and q got share as many digits (of the 24 a float keeps)
// as the bare Sobol' points at their indices do, in both coordinates. A wrong index fails it.
void check_order(const Sampler& s, unsigned pad, unsigned p, unsigned q) {
  const unsigned i = zsobol_index_of(s, p, pad), j = zsobol_index_of(s, q, pad);
  const Vec2f a = zsobol_pair(s, p, 0u, pad), b = zsobol_pair(s, q, 0u, pad);
  const auto bits = [](float x) { return unsigned(x * 16777216.0f) << 8; };
  const auto digits = [](int n) { return n < 24 ? n : 24; };
  if (digits(shared_digits(bits(a.x), bits(b.x))) !=
          digits(shared_digits(sobol_first(i), sobol_first(j))) ||
      digits(shared_digits(bits(a.y), bits(b.y))) !=
          digits(shared_digits(sobol_second(i), sobol_second(j))))
    throw std::logic_error("the zsobol order here no longer matches the sampler's points: "
                           "zsobol_pair's seed changed in samplers.h");
}

int run(const Options& o, const CLI::App& app) {
  check(o, app);
  const SamplerKind kind = parse_sampler(o.sampler);
  const Extent extent{o.width, o.height};
  const Sampler sampler = make_sampler(kind, extent, o.count);
  const unsigned vertex = unsigned(o.vertex), dimension = unsigned(o.dimension);
  check_output_path(o.output, "CSV file");
  if (!o.order.empty()) check_output_path(o.order, "CSV file");

  write_output_file(o.output, "CSV file", [&](std::FILE* file) {
    std::fprintf(file, "pixel,sample,u,v\n");
    // %.9g: every float's digits, so a reader gets the sampler's numbers exactly.
    const auto row = [&](unsigned pixel, unsigned sample) {
      std::fprintf(file, "%u,%u,%.9g,%.9g\n", pixel, sample,
                   double(sample_number(sampler, pixel, sample, vertex, dimension)),
                   double(sample_number(sampler, pixel, sample, vertex, dimension + 1)));
    };
    if (o.image)
      for (unsigned pixel = 0; pixel < unsigned(extent.pixel_count()); ++pixel) row(pixel, 0);
    else
      for (unsigned sample = 0; sample < unsigned(o.count); ++sample)
        row(unsigned(o.pixel), sample);
  });
  std::cout << "wrote " << o.output << " ("
            << (o.image
                    ? std::to_string(extent.pixel_count()) + " pixels' sample 0"
                    : std::to_string(o.count) + " samples of pixel " + std::to_string(o.pixel))
            << ", " << to_string(kind) << ", vertex " << vertex << ", dimensions " << dimension
            << " and " << dimension + 1 << ")\n";

  if (!o.order.empty()) {
    const unsigned pad = vertex * k_pads_per_vertex + dimension / 2;
    write_output_file(o.order, "CSV file", [&](std::FILE* file) {
      std::fprintf(file, "pixel,x,y,morton,index\n");
      for (unsigned pixel = 0; pixel < unsigned(extent.pixel_count()); ++pixel) {
        const unsigned x = pixel % sampler.width, y = pixel / sampler.width;
        check_order(sampler, pad, pixel, 0u);
        check_order(sampler, pad, pixel, (pixel + 1u) % unsigned(extent.pixel_count()));
        std::fprintf(file, "%u,%u,%u,%u,%u\n", pixel, x, y, morton_code(x, y),
                     zsobol_index_of(sampler, pixel, pad));
      }
    });
    std::cout << "wrote " << o.order << " (each pixel's Morton code and zsobol index)\n";
  }
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  CLI::App app{"Chapter 11: a sampler's points, from samplers.h's sample_number, as CSV",
               "ch11_sample_points"};
  Options o;
  app.add_option("--sampler", o.sampler, "independent, stratified, sobol or zsobol")
      ->capture_default_str();
  app.add_option("--count", o.count,
                 "Samples per pixel: the points written, and the count the sampler spreads "
                 "evenly (stratified's grid, zsobol's net)")
      ->check(CLI::Range(1LL, k_max_points))
      ->capture_default_str();
  app.add_option("--pixel", o.pixel, "The pixel whose samples are written (y * width + x)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--vertex", o.vertex,
                 "The path vertex: 0 the camera's point in its pixel, k the k-th surface")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  app.add_option("--dimension", o.dimension,
                 "The pad's first dimension at that vertex (0, 2, 4 or 6): u is it, v the next")
      ->check(CLI::Range(0, int(k_dimensions) - 2))
      ->capture_default_str();
  add_image_size_options(app, o.width, o.height);
  app.add_flag("--image", o.image,
               "Sample 0 of every pixel of the image instead of one pixel's samples");
  app.add_option("--order", o.order,
                 "With --image and zsobol: also each pixel's Morton code and index in the "
                 "image-wide sequence, to this .csv file");
  app.add_option("--output", o.output, "The points, a .csv file (pixel,sample,u,v)")
      ->capture_default_str();
  return run_main(app, argc, argv, [&] { return run(o, app); });
}
