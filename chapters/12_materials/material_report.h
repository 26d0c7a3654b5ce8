// Chapter 12: the program's rows beyond chapter 11's kernel rows: chapter 11's tracer on the
// same geometry, the texture filters and the two ways of reading textures, each timed and
// each with its aliasing measured as an error, and the energy compensation's cost.
#pragma once

#include "material_render.h"
#include "rt/report.h"

namespace rt::ch12 {

// The base-colour images' distance from a supersampled reference: what texture aliasing is,
// measured.
inline constexpr int k_aliasing_reference_samples = 256;

// Adds to `report`:
// - chapter 11's persistent tracer on the scene's geometry (every material Lambertian with
//   its base colour, no textures), and this renderer's Mrays/s against it;
// - per texture filter (and on the GPU per read: texture objects, plain loads): the time per
//   sample of the path-traced image and the RMSE of the pixel-centre base colour against the
//   mean of k_aliasing_reference_samples jittered point-sampled ones (when the scene has
//   textures);
// - the time per sample with the energy compensation left out (when the scene has specular
//   materials).
// Each timing is `frames` passes (0: the protocol's count). The renderer's options are left as
// they were found; its sums are emptied.
void add_material_rows(MaterialRenderer& renderer, const MaterialScene& scene,
                       const RenderSettings& settings, const CameraSpec& camera, Extent extent,
                       int frames, Report& report);

// The root mean square difference of two images, over pixels and channels.
double rms_difference(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b);

} // namespace rt::ch12
