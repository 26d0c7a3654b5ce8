// Chapter 08: shaded frames through the kept memory path. See kept_render.h.
#include "kept_render.h"

#include "bvh_render.cuh"

namespace rt::ch08 {

void render_kept_shaded(Backend backend, unsigned features, const KeptSceneView& scene,
                        const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                        ch06::ShadedPixelRecord* records, Vec3f* radiance) {
  ch07::render_shaded_through(backend, features, scene, camera, extent, pixels, records,
                              radiance);
}

} // namespace rt::ch08
