// Chapter 12: ray cones, which choose a texture's mip level at each hit (Akenine-Moller et al.,
// "Texture Level of Detail Strategies for Real-Time Ray Tracing", Ray Tracing Gems, 2019,
// chapter 20, and "Improved Shader and Texture Level of Detail Using Ray Cones", JCGT 2021).
// A camera ray stands for the pixel it leaves from: a thin cone whose width grows with the
// distance travelled. Where it meets a triangle, the level is the one whose texels are about
// as wide as the cone's footprint there, so a texture far away or seen at a slant is read from
// a smaller level instead of aliasing.
#pragma once

#include <cmath>

#include "rt/hd.h"
#include "rt/vec.h"

namespace rt::ch12 {

// [listing:ray_cone]
struct RayCone {
  float width = 0.0f;  // the cone's width where the ray is now, in world units
  float spread = 0.0f; // its angle, in radians: how fast the width grows with distance
};

// The spread of a pinhole camera's rays: the angle one pixel subtends at the centre of the
// image, atan(2 tan(vfov / 2) / height). tan_half_vfov is chapter 03's PinholeCamera's.
RT_HD inline float pinhole_spread_angle(float tan_half_vfov, int height_pixels) {
  return atanf(2.0f * tan_half_vfov / static_cast<float>(height_pixels));
}

// A camera ray's cone: a point at the eye, widening by the pixel's angle.
RT_HD inline RayCone camera_ray_cone(float tan_half_vfov, int height_pixels) {
  return {0.0f, pinhole_spread_angle(tan_half_vfov, height_pixels)};
}

// The cone after the ray has travelled a distance t.
RT_HD inline RayCone propagate(RayCone cone, float t) {
  return {cone.width + cone.spread * t, cone.spread};
}
// [/listing:ray_cone]

// [listing:ray_cone_lod]
// The part of the level of detail that belongs to the triangle and the texture alone, the same
// for every hit on it: 0.5 log2(texel area / world area), where the texel area is the
// triangle's area in uv times the texture's width * height texels (both areas doubled, as the
// cross products give them; the ratio does not mind). A triangle whose uv are all on a line
// (texel area 0: the texture is constant across it) or that has no area returns 0: any level
// reads the same there.
RT_HD inline float triangle_lod_constant(Vec3f p0, Vec3f p1, Vec3f p2, Vec2f uv0, Vec2f uv1,
                                         Vec2f uv2, int texture_width, int texture_height) {
  const Vec2f a = uv1 - uv0, b = uv2 - uv0;
  const float uv_area = absolute(difference_of_products(a.x, b.y, a.y, b.x));
  const float texel_area =
      static_cast<float>(texture_width) * static_cast<float>(texture_height) * uv_area;
  const float world_area = length(cross(p1 - p0, p2 - p0));
  if (!(texel_area > 0.0f) || !(world_area > 0.0f)) return 0.0f;
  const float constant = 0.5f * log2f(texel_area / world_area);
  return absolute(constant) < 1e30f ? constant : 0.0f; // inf / inf is NaN: 0 as well
}

// Below this |cos| a hit is grazing: the footprint, width / |cos|, would stretch without
// bound. The level it gives, log2(1e4) = 13.3 more, is already past most textures' last level.
inline constexpr float k_min_cone_cosine = 1e-4f;
// The largest level of detail returned: the last level of the largest texture (textures.h).
inline constexpr float k_max_cone_lod = 15.0f;

// The level of detail at a hit: the triangle's constant plus log2 of the cone's width, plus
// log2(1 / |cos|) for the footprint's stretch on a surface seen at a slant (cos: the ray's
// direction with the surface's normal, both unit length). Always finite, in [0,
// k_max_cone_lod]: a cone of width 0 (at the eye) reads level 0, a grazing one the last.
RT_HD inline float cone_texture_lod(float triangle_constant, RayCone cone,
                                    float cos_incidence) {
  const float cosine = absolute(cos_incidence) >= k_min_cone_cosine
                           ? absolute(cos_incidence)
                           : k_min_cone_cosine; // NaN too
  const float width = absolute(cone.width);
  if (!(width > 0.0f)) return 0.0f;
  const float lod = triangle_constant + log2f(width) - log2f(cosine);
  return lod >= 0.0f ? (lod <= k_max_cone_lod ? lod : k_max_cone_lod) : 0.0f;
}
// [/listing:ray_cone_lod]

// [listing:ray_cone_bounce]
// How a bounce changes the cone's spread. The papers add the surface's curvature (twice it
// for a mirror); the course's triangles are flat, so a mirror or a smooth interface leaves the
// spread as it is. A rough lobe scatters the ray over an angle of about its GGX alpha (the
// spread of its microfacet normals, in radians for small alpha): the course adds alpha, a
// heuristic, not the papers' rule, which covers only mirrors. A diffuse bounce scatters over
// the whole hemisphere: the cone becomes very wide (a quarter turn), so what it reads next
// comes from coarse levels, as the blur of a diffuse bounce would make of it anyway. The
// width, where the ray is, stays: it is the footprint the next leg starts from.
enum class ConeBounce : int { specular, rough, diffuse };

inline constexpr float k_diffuse_cone_spread = 1.5707964f; // pi / 2

RT_HD inline RayCone bounce_cone(RayCone cone, ConeBounce bounce, float alpha) {
  switch (bounce) {
  case ConeBounce::specular:
    return cone;
  case ConeBounce::rough:
    return {cone.width, min_of(cone.spread + absolute(alpha), k_diffuse_cone_spread)};
  case ConeBounce::diffuse:
    break;
  }
  return {cone.width, max_of(cone.spread, k_diffuse_cone_spread)};
}
// [/listing:ray_cone_bounce]

} // namespace rt::ch12
