// Chapter 11, second part: where the numbers of a path come from. Every sampler here is a pure
// function of (pixel, sample index, vertex, dimension), like path_random.h's hash, so that the
// megakernel, the persistent threads and the wavefront, on either backend, draw the same
// numbers for the same path and give the same sums bit for bit. They differ in how the numbers
// of one pixel's samples sit against one another:
//   independent  each number a hash: no two samples know of each other;
//   stratified   each pair of dimensions cut into a grid of cells, one sample in each;
//   sobol        each pair a shuffled, scrambled Sobol' (0,2)-sequence: stratified at every
//                power of two, on every elementary interval, in any prefix;
//   zsobol       one Sobol' sequence spread over the whole image in Morton order, so that
//                neighbouring pixels hold complementary samples and their errors cancel when
//                the eye averages them: the error becomes blue noise.
// A path's dimensions are consumed in pairs ("pads"): vertex v's dimensions 2k and 2k + 1 form
// pad 4v + k, and each pad is an independent 2D point set, decorrelated from the others by its
// own seed. Pairing loses the joint stratification of, say, the camera sample with the first
// bounce, which is why the gain of these samplers shrinks as paths grow longer.
#pragma once

#include "path_random.h"
#include "rt/hd.h"
#include "rt/launch.h"
#include "rt/vec.h"

namespace rt::ch11 {

enum class SamplerKind : int { independent, stratified, sobol, zsobol };

// A sampler as the kernels read it: its kind and what it needs of the image and of the sample
// count (make_sampler fills it in).
struct Sampler {
  SamplerKind kind = SamplerKind::independent;
  unsigned block = 1;           // stratified: the samples per pixel spread over one grid
  unsigned cells = 1;           // stratified: the grid's cells per side, floor(sqrt(block))
  unsigned log2_block = 0;      // zsobol: log2 of the samples per pixel of one image-wide net
                                // (below 32)
  unsigned width = 1;           // zsobol: the image's width, to find (x, y) from a pixel
  unsigned log2_resolution = 0; // zsobol: log2 of the square, a power of two, holding the image
};

// Pads per vertex: k_dimensions (path_random.h) dimensions, two at a time.
inline constexpr unsigned k_pads_per_vertex = k_dimensions / 2;

// ---- bits -----------------------------------------------------------------------------------

// The bits of x in reverse order (bit 0 becomes bit 31).
RT_HD inline unsigned reverse_bits(unsigned x) {
#if RT_ON_DEVICE
  return __brev(x);
#else
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
  x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
  return (x >> 16) | (x << 16);
#endif
}

// [listing:owen_scramble]
// Owen's nested uniform scrambling of a 32-bit fraction (bit 31 is the 1/2 digit), by a hash
// in the manner of Laine and Karras 2011 and Burley 2020. Owen flips each digit with a coin
// that depends only on the digits above it: the first digit by one coin, the second by one of
// two coins chosen by the first, and so on. Multiplying by an even constant sends every bit
// only towards the more significant end, so on the bit-reversed number (digit 1/2 at the
// bottom) a chain of x ^= x * even flips each digit by a function of the digits before it:
// exactly Owen's dependence. Adding the seed first makes the coins a function of the seed.
RT_HD inline unsigned owen_scramble(unsigned x, unsigned seed) {
  x = reverse_bits(x);
  x += seed;
  x ^= x * 0x6c50b47cu; // Laine and Karras's constants
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return reverse_bits(x);
}
// [/listing:owen_scramble]

// [listing:sobol_pair]
// The first two dimensions of Sobol's sequence as 32-bit fractions. The first is van der
// Corput's: the index's bits mirrored about the binary point. The second multiplies the
// index's bits by its generator matrix, whose columns are the direction numbers of the
// primitive polynomial x + 1: Pascal's triangle mod 2, so that digit j of the result (worth
// 2^-(j+1)) is the XOR of the index's bits k with C(k, j) odd, which by Lucas's theorem are
// the k whose binary digits include all of j's. Five shift-and-mask steps form those XORs for
// all 32 digits at once (a transform over subsets of the five bits that number a digit), then
// the digits are mirrored into place. Together the two are a (0,2)-sequence: any 2^m
// consecutive points starting at a multiple of 2^m put exactly one point in every box of area
// 2^-m whose sides are powers of two (an elementary interval).
RT_HD inline unsigned sobol_first(unsigned index) { return reverse_bits(index); }
RT_HD inline unsigned sobol_second(unsigned index) {
  unsigned x = index; // bit j: index bit j, then the XOR over the k that include j
  x ^= (x >> 1) & 0x55555555u;
  x ^= (x >> 2) & 0x33333333u;
  x ^= (x >> 4) & 0x0f0f0f0fu;
  x ^= (x >> 8) & 0x00ff00ffu;
  x ^= (x >> 16) & 0x0000ffffu;
  return reverse_bits(x);
}
// [/listing:sobol_pair]

// A 32-bit fraction to a float in [0, 1): its top 24 bits, all exactly representable.
RT_HD inline float unit_float(unsigned bits) { return float(bits >> 8) * (1.0f / 16777216.0f); }

// A hash of several words, each folded into the last step's output (path_random.h's way).
RT_HD inline unsigned hash_words(unsigned a, unsigned b) { return pcg_hash(pcg_hash(a) + b); }
RT_HD inline unsigned hash_words(unsigned a, unsigned b, unsigned c) {
  return pcg_hash(hash_words(a, b) + c);
}

// ---- stratified -----------------------------------------------------------------------------

// [listing:permute_index]
// Element i of a random permutation of 0 .. n - 1 chosen by `seed`, without a table: a
// bijection of the smallest power-of-two range holding n (each step, an XOR with a constant,
// a multiplication by an odd number, an XOR with the number shifted right, is invertible
// modulo a power of two), applied again while the result falls outside 0 .. n - 1. Applying a
// bijection of a finite set again walks round its cycle, which must come back into 0 .. n - 1
// (to i itself at worst), so the loop ends; it is expected to run fewer than two times.
// These few steps do not reach every permutation with equal odds, and when n is not a power
// of two the walk favours some places: permute_index(0, 3, seed) would be 1 half the time.
// So the result is finally turned round the circle 0 .. n - 1 by a random offset of its own:
// still a permutation, and now every i goes to every place with the same odds 1 / n, which is
// all that keeps a stratified sample uniform (an unbiased estimate) when a block is cut short.
RT_HD inline unsigned permute_index(unsigned i, unsigned n, unsigned seed) {
  unsigned mask = n - 1;
  mask |= mask >> 1;
  mask |= mask >> 2;
  mask |= mask >> 4;
  mask |= mask >> 8;
  mask |= mask >> 16;
  do {
    i ^= seed & mask;
    i = (i * 0x9e3779b1u) & mask;
    i ^= i >> 1;
    i = (i * (pcg_hash(seed) | 1u)) & mask;
    i ^= i >> 3;
    i = (i + (seed >> 11)) & mask;
    i ^= i >> 2;
  } while (i >= n);
  // An offset in 0 .. n - 1: a 32-bit hash scaled to n, every value within 2^-32 of 1 / n.
  const auto offset =
      unsigned((static_cast<unsigned long long>(pcg_hash(seed ^ 0x68e31da4u)) * n) >> 32);
  const unsigned turned = i + offset;
  return turned >= n ? turned - n : turned;
}
// [/listing:permute_index]

// [listing:stratified_number]
// Jittered stratification: the samples are taken in blocks of `block`; in each block the first
// cells^2 samples of a pad go one to a cell of a cells x cells grid, in a random order of the
// cells chosen per pixel, pad and block, each at a uniform point of its cell. The block's
// remaining samples (block is not always a square) are independent. Every sample is uniform
// over the square, so the estimate stays unbiased; in a block, the cells share the square out
// evenly, which removes the variance between cells.
RT_HD inline float cell_coordinate(unsigned along, unsigned jitter, unsigned cells) {
  // (along + jitter / 2^24) / cells in 24-bit fixed point, rounded down: below 1 always.
  const auto fixed = (static_cast<unsigned long long>(along) << 24 | jitter) / cells;
  return float(static_cast<unsigned>(fixed)) * (1.0f / 16777216.0f);
}
RT_HD inline Vec2f stratified_pair(const Sampler& s, unsigned pixel, unsigned sample,
                                   unsigned pad) {
  const unsigned block = sample / s.block, j = sample % s.block;
  const unsigned seed = hash_words(pixel, pad, block);
  const unsigned jitter_x = hash_words(seed, j, 0) >> 8, jitter_y = hash_words(seed, j, 1) >> 8;
  const unsigned cells = s.cells * s.cells;
  if (j >= cells) return {cell_coordinate(0, jitter_x, 1), cell_coordinate(0, jitter_y, 1)};
  const unsigned cell = permute_index(j, cells, seed);
  return {cell_coordinate(cell % s.cells, jitter_x, s.cells),
          cell_coordinate(cell / s.cells, jitter_y, s.cells)};
}
// [/listing:stratified_number]

// ---- Sobol', padded -------------------------------------------------------------------------

// The Sobol' point at `index` with each coordinate Owen scrambled. Its two seeds are made
// from one random `seed` by two different multiply-adds (bijections of 32-bit words): as
// random as the seed, distinct from it and from each other, for a multiply where a hash would
// cost six.
RT_HD inline Vec2f scrambled_sobol_pair(unsigned index, unsigned seed) {
  return {unit_float(owen_scramble(sobol_first(index), seed * 0x9e3779b9u + 0x7f4a7c15u)),
          unit_float(owen_scramble(sobol_second(index), seed * 0x85ebca6bu + 0xc2b2ae35u))};
}

// [listing:sobol_number]
// Burley's shuffled and scrambled Sobol': per pixel and pad, the sample index is itself Owen
// scrambled (a "shuffle": 2^m consecutive samples from a multiple of 2^m become the Sobol'
// points of another such run, so every power-of-two prefix is still a (0,2)-net), and each
// coordinate is Owen scrambled with its own seed, which makes every point uniform and the pads
// independent. Two pixels, two pads, draw unrelated nets.
RT_HD inline Vec2f sobol_pair(unsigned pixel, unsigned sample, unsigned pad) {
  const unsigned seed = hash_words(pixel, pad);
  const unsigned index = owen_scramble(sample, seed);
  return scrambled_sobol_pair(index, seed);
}
// [/listing:sobol_number]

// ---- Sobol' in Morton order -----------------------------------------------------------------

// The bits of x (16 at most) spread to the even bit positions: 0b1011 -> 0b1000101.
RT_HD inline unsigned spread_bits(unsigned x) {
  x &= 0x0000ffffu;
  x = (x | (x << 8)) & 0x00ff00ffu;
  x = (x | (x << 4)) & 0x0f0f0f0fu;
  x = (x | (x << 2)) & 0x33333333u;
  x = (x | (x << 1)) & 0x55555555u;
  return x;
}
// The Morton (Z-order) code of (x, y): their bits interleaved, y's above x's.
RT_HD inline unsigned morton_code(unsigned x, unsigned y) {
  return spread_bits(x) | spread_bits(y) << 1;
}

// [listing:permute_digit]
// Digit d (0 .. 3) under permutation k (0 .. 23) of the four digits. Every permutation of four
// things is an affine map of d's two bits, d -> M d XOR a: M one of the six invertible 2 x 2
// matrices of bits (its columns c0 and c1 two different non-zero digits) and a one of the four
// digits, 6 x 4 = 24. So no table: k picks the columns and the offset.
RT_HD inline unsigned permute_digit(unsigned d, unsigned k) {
  const unsigned m = k % 6u, a = k / 6u;
  const unsigned c0 = 1u + m % 3u, c1 = 1u + (m % 3u + 1u + m / 3u) % 3u;
  return ((d & 1u) ? c0 : 0u) ^ ((d & 2u) ? c1 : 0u) ^ a;
}
// [/listing:permute_digit]

// [listing:zsobol_index]
// The Sobol' index of a pixel's sample in an image-wide sequence: the pixel's Morton code with
// the sample's bits below it, so that each pixel owns an aligned run of 2^log2_block indices
// (its own (0,2)-net), each 2 x 2 quad of pixels a run four times longer, and so on up to the
// whole image. Each base-4 digit (a choice among the four children of a quad) is then
// permuted, by one of the 24 permutations chosen by a hash of the digits above it: a nested
// random shuffle of the quads that keeps every run aligned, so every pixel and every quad of
// pixels still holds a net, but which pixel gets which part of the net is random. Ahmed and
// Wonka 2020 showed that this ordering spreads the error as blue noise.
// The error's blue noise lives at the scale of a few pixels, so only the digits inside a tile
// of 2^k_zsobol_tile_digits pixels a side (and the sample's) are permuted one by one; the
// tile's number above them, the coarse digits, is Owen scrambled in one go. That still maps
// each tile to an aligned run of its own, and halves the work at 1920 x 1080.
inline constexpr unsigned k_zsobol_tile_digits = 4; // 16 x 16 pixels
RT_HD inline unsigned zsobol_index(const Sampler& s, unsigned pixel, unsigned sample,
                                   unsigned seed) {
  const unsigned x = pixel % s.width, y = pixel / s.width;
  const unsigned in_block = sample & ((1u << s.log2_block) - 1u); // log2_block < 32
  const unsigned m = morton_code(x, y) << s.log2_block | in_block;
  const unsigned tile_digits =
      s.log2_resolution < k_zsobol_tile_digits ? s.log2_resolution : k_zsobol_tile_digits;
  const unsigned low_bits = 2 * tile_digits + s.log2_block; // the tile's pixels and samples
  const unsigned high_bits = 2 * s.log2_resolution - 2 * tile_digits; // the tile's number
  const unsigned tile = high_bits == 0 ? 0u : m >> low_bits;
  // The tile's number, Owen scrambled as the top high_bits bits of a word: a bijection.
  unsigned index = high_bits == 0 ? 0u
                                  : owen_scramble(tile << (32 - high_bits), seed) >>
                                        (32 - high_bits) << low_bits;
  unsigned h = pcg_hash(seed + tile); // a hash of the digits above the current one
  // An odd log2_block leaves one binary digit at the bottom, flipped by a coin of its own.
  const unsigned lowest = s.log2_block & 1u;
  for (int shift = int(low_bits) - 2; shift >= int(lowest); shift -= 2) {
    const unsigned digit = (m >> shift) & 3u;
    index |= permute_digit(digit, (h >> 8) % 24u) << shift;
    h = pcg_hash(h + digit + 1u); // a chain: one step a digit
  }
  if (lowest) index |= (m & 1u) ^ ((h >> 16) & 1u);
  return index;
}
// [/listing:zsobol_index]

// The zsobol sampler's pair: the pad's Sobol' point at zsobol_index, each coordinate Owen
// scrambled. The seeds depend on the pad and on the block (the samples beyond the first
// 2^log2_block of a pixel start a new, independent net), never on the pixel: the whole image
// shares one net.
RT_HD inline Vec2f zsobol_pair(const Sampler& s, unsigned pixel, unsigned sample,
                               unsigned pad) {
  const unsigned block = sample >> s.log2_block;
  const unsigned seed = hash_words(pad, block, 0x5bd1e995u);
  return scrambled_sobol_pair(zsobol_index(s, pixel, sample, seed), seed);
}

// [listing:sampler_number]
// The two numbers in [0, 1) of (pixel, sample, vertex) for dimensions `first` and first + 1
// (first even: one pad) by the sampler's kind, and one number alone. A pad's work (its seed,
// its cell, its Sobol' index) is done once for both numbers. The independent sampler is
// path_random.h's hash, number for number.
RT_HD inline Vec2f sample_pair(const Sampler& s, unsigned pixel, unsigned sample,
                               unsigned vertex, unsigned first) {
  const unsigned pad = vertex * k_pads_per_vertex + first / 2;
  switch (s.kind) {
  case SamplerKind::stratified:
    return stratified_pair(s, pixel, sample, pad);
  case SamplerKind::sobol:
    return sobol_pair(pixel, sample, pad);
  case SamplerKind::zsobol:
    return zsobol_pair(s, pixel, sample, pad);
  default:
    return {sample_number(pixel, sample, vertex, first),
            sample_number(pixel, sample, vertex, first + 1)};
  }
}
RT_HD inline float sample_number(const Sampler& s, unsigned pixel, unsigned sample,
                                 unsigned vertex, unsigned dimension) {
  if (s.kind == SamplerKind::independent)
    return sample_number(pixel, sample, vertex, dimension);
  const Vec2f p = sample_pair(s, pixel, sample, vertex, dimension & ~1u);
  return (dimension & 1u) == 0 ? p.x : p.y;
}
// [/listing:sampler_number]

// The sampler of `kind` for an image of `extent` whose pixels take `samples` samples
// (stratified's block, rounded up to a power of two for zsobol; 0: 16). The zsobol index must
// fit in 32 bits: 2 log2(side) for the pixel and the rest, at most, for the samples.
inline Sampler make_sampler(SamplerKind kind, Extent extent, int samples) {
  Sampler s;
  s.kind = kind;
  const unsigned n = samples > 0 ? unsigned(samples) : 16u;
  s.block = n;
  s.cells = 1;
  while ((s.cells + 1) * (s.cells + 1) <= n) ++s.cells;
  s.width = extent.width > 0 ? unsigned(extent.width) : 1u;
  const unsigned side = unsigned(extent.width > extent.height ? extent.width : extent.height);
  while ((1u << s.log2_resolution) < side && s.log2_resolution < 16) ++s.log2_resolution;
  unsigned log2_samples = 0;
  while ((1ull << log2_samples) < n) ++log2_samples;
  const unsigned room = s.log2_resolution > 0 ? 32 - 2 * s.log2_resolution : 31;
  s.log2_block = log2_samples < room ? log2_samples : room;
  return s;
}

} // namespace rt::ch11
