// Chapter 09: batches of rays through a wide tree on either backend. The GPU kernel is one
// thread per ray, rays in and hits out, as chapter 07's; the CPU runs the same traversal on
// its threads. Each function exists for the views (WideTreeView) of the four stored layouts:
// WideNode<4> and WideNode<8> with aligned triangles, CompressedNode, and WideNode<4> with
// packed triangles; the GPU variants at the end (tiles, a shared stack, persistent threads,
// sorted rays) for the last alone.
#pragma once

#include <span>

#include "bvh_trace.h"
#include "ray_sort.h"
#include "rt/device_buffer.h"
#include "rt/launch.h"
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

// [listing:ray_order]
// Which ray each GPU thread takes. A batch is a list, and thread i takes ray i. But the rays of
// a whole image, one per pixel in row order (the benchmark's camera rays, and its secondary
// rays in a room where every pixel hits), can instead go out a tile of 8 x 4 pixels to a warp
// (rt::PixelTiles), as a 2-D launch over the image gives them out: the rays of a warp then
// leave from a square of pixels, not a strip of one row. The hits go to the same slots.
struct RayOrder {
  PixelTiles tiles{0, 0}; // an image of no pixels: the list order
  // Tiles where `count` rays are exactly a width x height image's; the list order otherwise
  // (a list of only the pixels that hit something is not an image).
  static RayOrder for_image(int count, int width, int height) {
    RayOrder order;
    if (width > 0 && height > 0 && static_cast<long long>(width) * height == count)
      order.tiles = PixelTiles(width, height);
    return order;
  }
  RT_HD bool tiled() const { return tiles.width > 0; }
  // The thread numbers to cover.
  RT_HD long long numbers(int count) const { return tiled() ? tiles.count() : count; }
  // The ray of thread `number` in `i`; false for a thread with none (past the image's edge).
  RT_HD bool ray_of(unsigned number, int count, int& i) const {
    if (!tiled()) {
      i = int(number);
      return number < unsigned(count);
    }
    int x = 0, y = 0;
    if (!tiles.pixel(number, x, y)) return false;
    i = y * tiles.width + x;
    return true;
  }
};
// [/listing:ray_order]

// `count` rays (device memory) into `hits` (device memory): closest or any hit, the rays taken
// in `order`.
template <class View>
void trace_wide_gpu(Query query, const View& tree, const RayF* rays, int count, MeshHit* hits,
                    RayOrder order = {});

// Registers per thread of the traversal kernel for a layout; needs a usable GPU.
template <class View> int wide_kernel_registers(Query query);

// The same on CPU threads (host memory).
template <class View>
void trace_wide_cpu(Query query, const View& tree, std::span<const RayF> rays,
                    std::span<MeshHit> hits);

// Three other ways of running the same traversal on the GPU, each ray's hit the same bit for
// bit (instantiated for the chapter's best tree, Wide4PackedBvh::View).

// 1. The first entries of each thread's stack in shared memory, the rest in local memory.
template <class View>
void trace_wide_gpu_shared_stack(Query query, const View& tree, const RayF* rays, int count,
                                 MeshHit* hits);
template <class View> int shared_stack_kernel_registers(Query query);

// 2. Persistent threads: as many blocks as the GPU holds at once, each warp taking 32 rays at a
// time from a counter in device memory until none are left. Made once per tracer: it owns the
// counter and knows how many blocks of its kernels fit on the GPU.
template <class View> class PersistentWideTracer {
public:
  PersistentWideTracer();
  void trace(Query query, const View& tree, const RayF* rays, int count, MeshHit* hits,
             RayOrder order = {});
  static int registers(Query query);

private:
  DeviceBuffer<unsigned> next_ray_;
  int resident_blocks_[2] = {}; // the closest-hit kernel's, the any-hit kernel's
};

// 3. The rays traced in the order of their keys (ray_sort.h): a kernel computes the keys, CUB
// sorts (key, index) pairs, and the trace kernel takes its rays through the sorted indices and
// writes each hit to its own ray's slot. Made once per tracer: it keeps the key, index and
// sort buffers, grown to the largest batch seen, so a launch allocates nothing.
template <class View> class SortedWideTracer {
public:
  explicit SortedWideTracer(const RaySortFrame& frame) : frame_(frame) {}
  void trace(Query query, const View& tree, const RayF* rays, int count, MeshHit* hits);
  static int registers(Query query); // the trace kernel's
  static int key_kernel_registers();

private:
  RaySortFrame frame_;
  DeviceBuffer<unsigned> keys_, sorted_keys_;
  DeviceBuffer<int> indices_, sorted_indices_;
  DeviceBuffer<unsigned char> sort_scratch_;
};

// The same on CPU threads: the keys, std::sort, then the rays in that order.
template <class View>
void trace_wide_sorted_cpu(Query query, const View& tree, const RaySortFrame& frame,
                           std::span<const RayF> rays, std::span<MeshHit> hits);

// Nodes read and triangles tested per ray, and the deepest stack (CPU, with counters).
template <class View>
ch07::TraversalWork measure_wide_work(Query query, const View& tree,
                                      std::span<const RayF> rays);

} // namespace rt::ch09
