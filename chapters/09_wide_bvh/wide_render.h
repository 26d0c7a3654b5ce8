// Chapter 09: shaded frames (chapter 06's shading, as in chapters 07 and 08) traced through
// the compressed wide tree or the 4-wide packed one, on either backend.
#pragma once

#include "rt/backend.h"
#include "shaded_frame.h"
#include "wide_scene.h"

namespace rt::ch09 {

// `scene` holds device pointers on the GPU backend and host pointers on the CPU.
void render_wide_shaded(Backend backend, unsigned features, const CompressedSceneView& scene,
                        const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                        ch06::ShadedPixelRecord* records = nullptr, Vec3f* radiance = nullptr);
void render_wide_shaded(Backend backend, unsigned features, const Wide4PackedSceneView& scene,
                        const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                        ch06::ShadedPixelRecord* records = nullptr, Vec3f* radiance = nullptr);

// [listing:wide_heat_map]
// Chapter 07's node-visit heat map through the compressed tree, in chapter 07's colours so that
// the two chapters' pictures compare: each pixel's camera ray (closest hit), coloured by the
// wide nodes it visited. One wide node stands for up to eight binary ones, so the same rays
// are darker here; where they stay bright, the wide boxes overlap as the binary ones did.
void render_wide_heat_map(Backend backend, const WideTreeView<CompressedNode>& tree,
                          const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels);
// [/listing:wide_heat_map]

} // namespace rt::ch09
