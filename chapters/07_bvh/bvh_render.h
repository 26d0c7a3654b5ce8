// Chapter 07: shaded frames (chapter 06's Lambertian shading, shadows and all) traced
// through the tree, on either backend, by a kernel specialised on the frame's features.
#pragma once

#include "bvh_scene.h"
#include "rt/backend.h"
#include "shaded_frame.h"

namespace rt::ch07 {

// `scene` holds device pointers on the GPU backend and host pointers on the CPU.
void render_bvh_shaded(Backend backend, unsigned features, const BvhSceneView& scene,
                       const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                       ch06::ShadedPixelRecord* records = nullptr, Vec3f* radiance = nullptr);

} // namespace rt::ch07
