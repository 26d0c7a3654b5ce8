// Chapter 09: shaded frames through the compressed tree. See wide_render.h.
#include "wide_render.h"

#include "bvh_render.cuh"
#include "heat_map.h"
#include "rt/launch.h"

namespace rt::ch09 {

void render_wide_shaded(Backend backend, unsigned features, const CompressedSceneView& scene,
                        const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                        ch06::ShadedPixelRecord* records, Vec3f* radiance) {
  ch07::render_shaded_through(backend, features, scene, camera, extent, pixels, records,
                              radiance);
}

void render_wide_shaded(Backend backend, unsigned features, const Wide4PackedSceneView& scene,
                        const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                        ch06::ShadedPixelRecord* records, Vec3f* radiance) {
  ch07::render_shaded_through(backend, features, scene, camera, extent, pixels, records,
                              radiance);
}

void render_wide_heat_map(Backend backend, const WideTreeView<CompressedNode>& tree,
                          const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels) {
  for_each_pixel(backend, extent, [=] RT_HD(int x, int y) {
    ch07::Counters counters;
    trace_wide<Query::closest>(tree, camera.ray_through_pixel(x, y), counters);
    pixels[y * extent.width + x] = ch07::heat_colour(counters.nodes);
  });
}

} // namespace rt::ch09
