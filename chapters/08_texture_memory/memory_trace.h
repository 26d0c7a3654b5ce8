// Chapter 08: batches of rays through the tree by each memory path, on either backend, and the
// primary rays made inside the traversal kernel with the camera and the tree as kernel
// parameters or in __constant__ memory. The triangle test is watertight throughout.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "bvh_trace.h"
#include "memory_paths.h"
#include "packed_bvh.h"
#include "protocol.h"
#include "rt/device_buffer.h"
#include "texture_object.h"

namespace rt::ch08 {

using ch03::RayF;
using ch04::MeshHit;
using ch07::Query;

// [listing:kept_path]
// The path later chapters build on: the fastest in this chapter's measurements (book/08).
inline constexpr MemoryPath k_kept_path = MemoryPath::float4;
using KeptTree = PackedTree<GlobalRecords>;
// [/listing:kept_path]

// One tree on the GPU in every layout: chapter 07's arrays, the 16-byte records and, when
// asked for, a texture object over each array of records. Owned.
class DeviceTrees {
public:
  DeviceTrees(const Bvh& bvh, const PackedBvh& packed, bool with_textures);

  BvhView global_tree() const { return structs_.view(); }
  ReadOnlyBvh ldg_tree() const { return read_only(structs_.view()); }
  PackedTree<GlobalRecords> float4_tree() const;
  PackedTree<ReadOnlyRecords> float4_ldg_tree() const;
  KeptTree kept() const; // the tree of k_kept_path
  std::size_t bytes(MemoryPath path) const;
  bool has_textures() const { return textures_; }

  // For the .cu files: the texture handles (0 for an empty tree).
  cudaTextureObject_t node_texture() const { return node_texture_.handle(); }
  cudaTextureObject_t triangle_texture() const { return triangle_texture_.handle(); }

private:
  ch07::DeviceBvh structs_;
  DeviceBuffer<float4> nodes_, triangles_;
  int node_count_ = 0;
  bool textures_ = false;
  TextureObject node_texture_, triangle_texture_;
};

// Device memory the trees take: the structs, the records, and nothing for the textures
// (a texture object is a view of memory already counted).
std::size_t device_tree_bytes(const Bvh& bvh);

// `count` rays (device memory) through `path`, closest or any hit, into `hits`.
void trace_rays_path_gpu(MemoryPath path, Query query, const DeviceTrees& trees,
                         const RayF* rays, int count, MeshHit* hits);

// The same on CPU cores (host memory): global and float4 only (check_runs_on).
void trace_rays_path_cpu(MemoryPath path, Query query, const Bvh& bvh, const PackedBvh& packed,
                         std::span<const RayF> rays, std::span<MeshHit> hits);

// Registers per thread of a path's traversal kernel; needs a usable GPU.
int path_kernel_registers(MemoryPath path, Query query);

// Where the primary-ray kernel finds the camera and the tree.
enum class ConstantsIn { parameters, constant_memory };
const char* to_string(ConstantsIn where);

// The protocol's primary rays made in the kernel (one thread per pixel, chapter 07's
// camera_ray) and traced through the kept path: no ray buffer read. For constant_memory the
// camera and the tree are copied to a __constant__ symbol here, before the launch; timing
// only launch() times the kernel alone.
class CameraTrace {
public:
  CameraTrace(const DeviceTrees& trees, const ch07::PinholeCamera& camera, ConstantsIn where);
  // The symbol is filled for this object: not copied, not moved.
  CameraTrace(const CameraTrace&) = delete;
  CameraTrace& operator=(const CameraTrace&) = delete;
  void launch(MeshHit* hits) const; // camera.width * camera.height hits, pixel order
  int registers() const;

private:
  KeptTree tree_;
  ch07::PinholeCamera camera_;
  ConstantsIn where_;
};

} // namespace rt::ch08
