// Chapter 08: shaded frames (chapter 06's shading, as in chapter 07) traced through the kept
// memory path, on either backend. On the CPU the read-only loads are plain reads.
#pragma once

#include "bvh_scene.h"
#include "memory_trace.h"
#include "rt/backend.h"
#include "shaded_frame.h"

namespace rt::ch08 {

using KeptSceneView = ch06::SceneViewOf<ch07::BvhGeometryOf<KeptTree>>;

// The packed tree in host memory, as the kept path reads it.
inline KeptTree host_kept_view(const PackedBvh& p) {
  return {{p.nodes.data(), p.triangles.data()}, p.node_count};
}

// `scene` holds device pointers on the GPU backend and host pointers on the CPU.
void render_kept_shaded(Backend backend, unsigned features, const KeptSceneView& scene,
                        const ch03::Camera<float>& camera, Extent extent, Rgba8* pixels,
                        ch06::ShadedPixelRecord* records = nullptr, Vec3f* radiance = nullptr);

} // namespace rt::ch08
