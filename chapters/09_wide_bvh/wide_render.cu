// Chapter 09: shaded frames through the compressed tree. See wide_render.h.
#include "wide_render.h"

#include "bvh_render.cuh"

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

} // namespace rt::ch09
