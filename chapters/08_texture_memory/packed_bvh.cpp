// Chapter 08: packing chapter 07's tree into 16-byte records. See packed_bvh.h.
#include "packed_bvh.h"

#include <cstring>

namespace rt::ch08 {

PackedBvh pack_bvh(const Bvh& bvh) {
  PackedBvh p;
  p.node_count = static_cast<int>(bvh.nodes.size());
  // A node's 64 bytes are already four 16-byte records: copied as they are.
  p.nodes.resize(bvh.nodes.size() * k_node_records);
  if (!bvh.nodes.empty())
    std::memcpy(p.nodes.data(), bvh.nodes.data(), bvh.nodes.size() * sizeof(BvhNode));
  p.triangles.reserve(bvh.triangles.size() * k_triangle_records);
  for (std::size_t k = 0; k < bvh.triangles.size(); ++k) {
    const TriangleF& t = bvh.triangles[k];
    float id_bits;
    std::memcpy(&id_bits, &bvh.triangle_ids[k], sizeof id_bits);
    p.triangles.push_back({t.v0.x, t.v0.y, t.v0.z, id_bits});
    p.triangles.push_back({t.v1.x, t.v1.y, t.v1.z, 0.0f});
    p.triangles.push_back({t.v2.x, t.v2.y, t.v2.z, 0.0f});
  }
  return p;
}

} // namespace rt::ch08
