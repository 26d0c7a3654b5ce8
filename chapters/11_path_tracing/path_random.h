// Chapter 11: random numbers without state. Each number a path uses is a hash of where it is
// used: the pixel, the sample index, the path vertex and the dimension at that vertex. No
// thread keeps a generator, so any backend, any launch order and any kernel split (the
// megakernel or the wavefront stages) draws the same numbers for the same path.
#pragma once

#include "rt/hd.h"

namespace rt::ch11 {

// What each path vertex draws, by dimension. Vertex 0 is the camera (dimensions 0 and 1 place
// the sample in its pixel); vertex k >= 1 is the k-th surface the path meets.
enum Dimension : unsigned {
  k_bsdf_u = 0,     // the cosine-weighted direction's two numbers
  k_bsdf_v = 1,     //
  k_roulette = 2,   // Russian roulette's survival draw
  k_light_pick = 3, // which emitting triangle next-event estimation samples
  k_light_u = 4,    // where on that triangle
  k_light_v = 5,    //
  k_dimensions = 8, // per vertex (two spare)
};

// A 32-bit permutation with good avalanche: a linear congruential step, then the output
// permutation of the PCG family (a random rotation by the high bits and a multiply).
// Jarzynski and Olano 2020 found it among the best trades of quality for speed on GPUs.
RT_HD inline unsigned pcg_hash(unsigned value) {
  const unsigned state = value * 747796405u + 2891336453u;
  const unsigned word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// [listing:sample_number]
// The number in [0, 1) of (pixel, sample, vertex, dimension): the hash applied once per
// coordinate, each step folding the next coordinate into the last step's output. 24 bits
// make a float in [0, 1) with every value exactly representable, so 1 is never returned.
RT_HD inline float sample_number(unsigned pixel, unsigned sample, unsigned vertex,
                                 unsigned dimension) {
  unsigned h = pcg_hash(pixel);
  h = pcg_hash(h + sample);
  h = pcg_hash(h + vertex * k_dimensions + dimension);
  return float(h >> 8) * (1.0f / 16777216.0f);
}
// [/listing:sample_number]

} // namespace rt::ch11
