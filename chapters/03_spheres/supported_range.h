// Chapter 03: the scales the float pipeline supports. Float spans 1.2e-38 to 3.4e38, but the
// ray tests multiply coordinates together, so the range of the coordinates themselves is far
// narrower: every program refuses a scene, a camera or a ray outside these bounds.
#pragma once

namespace rt::ch03 {

// [listing:supported_range]
// Largest |coordinate| of any point: a vertex, the eye, the target, a ray's origin. The
// deepest product the course forms is chapter 04's watertight t: an edge function (a product
// of two coordinate differences) times a third difference, below 200 M^3 for coordinates up to
// M. At M = 1e10 that is 2e32, a million times below float's largest value; the camera basis
// (normalize(target - eye)) and the sphere test square lengths only, 1e21.
inline constexpr double k_max_coordinate = 1e10;

// Shortest length that counts: eye to target, and the side of the smallest triangle that is
// not flat (of zero area) in float. At s = 1e-10 the watertight test's products, ~s^2 = 1e-20,
// are 1e11 above the point (2^-102, 2e-31) where their exact rounding error would be lost to
// float underflow, and t's product, ~s^3, is 1e8 above float's smallest normal number.
// Chapter 03's spawn offset stops shrinking at 2^-32 (2.3e-10), about the same scale.
inline constexpr double k_min_length = 1e-10;
// [/listing:supported_range]

} // namespace rt::ch03
