// Chapter 07: shaded frames through the tree. See bvh_render.h.
#include "bvh_render.h"

#include "bvh_render.cuh"

namespace rt::ch07 {

void render_bvh_shaded(Backend backend, unsigned features, const BvhSceneView& scene,
                       const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                       ch06::ShadedPixelRecord* records, Vec3f* radiance) {
  render_shaded_through(backend, features, scene, camera, extent, pixels, records, radiance);
}

} // namespace rt::ch07
