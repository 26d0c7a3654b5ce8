// Chapter 09: batches of rays through a wide tree on either backend. The GPU kernel is one
// thread per ray, rays in and hits out, as chapter 07's; the CPU runs the same traversal on
// its threads. Each function exists for the views (WideTreeView) of the four stored layouts:
// WideNode<4> and WideNode<8> with aligned triangles, CompressedNode, and WideNode<4> with
// packed triangles.
#pragma once

#include <span>

#include "bvh_trace.h"
#include "rt/device_buffer.h"
#include "wide_bvh.h"

namespace rt::ch09 {

using ch03::RayF;
using ch04::MeshHit;
using ch07::Query;

// A wide tree copied to the GPU, owned.
template <class Node, class Triangles = AlignedTriangles> class DeviceWideTree {
public:
  using Record = typename Triangles::Record;
  explicit DeviceWideTree(const WideTree<Node, Triangles>& tree)
      : nodes_(std::span<const Node>(tree.nodes)),
        triangles_(std::span<const Record>(tree.triangles)) {}
  WideTreeView<Node, Triangles> view() const {
    return {nodes_.data(), triangles_.data(), static_cast<int>(nodes_.size())};
  }

private:
  DeviceBuffer<Node> nodes_;
  DeviceBuffer<Record> triangles_;
};

// `count` rays (device memory) into `hits` (device memory): closest or any hit.
template <class View>
void trace_wide_gpu(Query query, const View& tree, const RayF* rays, int count, MeshHit* hits);

// Registers per thread of the traversal kernel for a layout; needs a usable GPU.
template <class View> int wide_kernel_registers(Query query);

// The same on CPU threads (host memory).
template <class View>
void trace_wide_cpu(Query query, const View& tree, std::span<const RayF> rays,
                    std::span<MeshHit> hits);

// Nodes read and triangles tested per ray, and the deepest stack (CPU, with counters).
template <class View>
ch07::TraversalWork measure_wide_work(Query query, const View& tree,
                                      std::span<const RayF> rays);

} // namespace rt::ch09
