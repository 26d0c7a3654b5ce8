// Chapter 08: rays through each memory path. See memory_trace.h.
#include "memory_trace.h"

#include <atomic>

#include "rt/cuda_check.h"
#include "rt/error.h"
#include "rt/kernel_info.h"
#include "rt/launch.h"
#include "traverse.h"

namespace rt::ch08 {
namespace {

using ch04::TriangleVariant;
constexpr TriangleVariant k_variant = TriangleVariant::watertight;
constexpr int k_block = 128; // threads per block, as in chapter 07

// [listing:path_kernel]
// Chapter 07's traversal kernel with the tree's type as a parameter: one instantiation per
// memory path, the traversal code the same in all of them.
template <Query kQuery, class Tree>
__global__ void path_trace_kernel(Tree tree, const RayF* rays, int count, MeshHit* hits) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  const ch07::TraceHit hit = ch07::trace_bvh<kQuery, k_variant>(tree, rays[i]);
  hits[i] = {hit.t, hit.triangle};
}
// [/listing:path_kernel]

PackedTree<TextureRecords> texture_tree(const DeviceTrees& trees) {
  if (!trees.has_textures())
    throw Error("the texture path needs the trees made with their texture objects");
  return {{trees.node_texture(), trees.triangle_texture()}, trees.global_tree().node_count};
}

// Calls fn(kernel, tree) with a path's kernel and the tree it reads; without trees (nullptr),
// with an empty tree (for the kernel's attributes).
template <Query kQuery, class Fn>
void with_path_kernel(MemoryPath path, const DeviceTrees* trees, Fn fn) {
  switch (path) {
  case MemoryPath::global:
    fn(path_trace_kernel<kQuery, BvhView>, trees ? trees->global_tree() : BvhView{});
    return;
  case MemoryPath::ldg:
    fn(path_trace_kernel<kQuery, ReadOnlyBvh>, trees ? trees->ldg_tree() : ReadOnlyBvh{});
    return;
  case MemoryPath::float4:
    fn(path_trace_kernel<kQuery, PackedTree<GlobalRecords>>,
       trees ? trees->float4_tree() : PackedTree<GlobalRecords>{});
    return;
  case MemoryPath::float4_ldg:
    fn(path_trace_kernel<kQuery, PackedTree<ReadOnlyRecords>>,
       trees ? trees->float4_ldg_tree() : PackedTree<ReadOnlyRecords>{});
    return;
  case MemoryPath::texture:
    fn(path_trace_kernel<kQuery, PackedTree<TextureRecords>>,
       trees ? texture_tree(*trees) : PackedTree<TextureRecords>{});
    return;
  }
  throw Error("unknown memory path");
}

template <class Fn>
void with_path_kernel(MemoryPath path, Query query, const DeviceTrees* trees, Fn fn) {
  if (query == Query::closest)
    with_path_kernel<Query::closest>(path, trees, fn);
  else
    with_path_kernel<Query::any>(path, trees, fn);
}

// [listing:camera_kernels]
// Primary rays made in the kernel: the camera and the tree as kernel parameters, or read from
// __constant__ memory. Both live in constant banks of the same cache; the kernel parameters
// are bank 0, filled at each launch, the __constant__ symbol is filled once by a copy.
struct CameraTraceArgs {
  ch07::PinholeCamera camera;
  KeptTree tree;
};

// A __constant__ variable cannot have a constructor to run, so the symbol is raw, aligned
// storage, and the kernel reads it as CameraTraceArgs.
__constant__ float4 c_camera_trace[(sizeof(CameraTraceArgs) + 15) / 16];

__device__ void camera_trace_pixel(const CameraTraceArgs& a, MeshHit* hits) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  const int width = a.camera.width;
  if (i >= width * a.camera.height) return;
  const RayF ray = ch07::camera_ray(a.camera, i % width, i / width);
  const ch07::TraceHit hit = ch07::trace_bvh<Query::closest, k_variant>(a.tree, ray);
  hits[i] = {hit.t, hit.triangle};
}

__global__ void camera_trace_kernel_parameters(CameraTraceArgs args, MeshHit* hits) {
  camera_trace_pixel(args, hits);
}

__global__ void camera_trace_kernel_constant(MeshHit* hits) {
  camera_trace_pixel(*reinterpret_cast<const CameraTraceArgs*>(c_camera_trace), hits);
}
// [/listing:camera_kernels]

std::atomic<const CameraTrace*> g_constant_owner{nullptr};

} // namespace

DeviceTrees::DeviceTrees(const Bvh& bvh, const PackedBvh& packed, bool with_textures)
    : structs_(bvh), nodes_(std::span<const float4>(packed.nodes)),
      triangles_(std::span<const float4>(packed.triangles)), node_count_(packed.node_count),
      textures_(with_textures) {
  if (packed.node_count != static_cast<int>(bvh.nodes.size()))
    throw Error("DeviceTrees: the packed tree is not this tree's");
  if (with_textures && node_count_ > 0) {
    node_texture_ = TextureObject(nodes_.data(), nodes_.size());
    triangle_texture_ = TextureObject(triangles_.data(), triangles_.size());
  }
}

PackedTree<GlobalRecords> DeviceTrees::float4_tree() const {
  return {{nodes_.data(), triangles_.data()}, node_count_};
}

PackedTree<ReadOnlyRecords> DeviceTrees::float4_ldg_tree() const {
  return {{nodes_.data(), triangles_.data()}, node_count_};
}

KeptTree DeviceTrees::kept() const { return float4_tree(); }

std::size_t DeviceTrees::bytes(MemoryPath path) const {
  return path == MemoryPath::global || path == MemoryPath::ldg
             ? structs_.bytes()
             : nodes_.bytes() + triangles_.bytes();
}

std::size_t device_tree_bytes(const Bvh& bvh) {
  const std::size_t structs =
      bvh.nodes.size() * sizeof(BvhNode) + bvh.triangles.size() * (sizeof(TriangleF) + 4);
  const std::size_t records = bvh.nodes.size() * sizeof(BvhNode) +
                              bvh.triangles.size() * k_triangle_records * sizeof(float4);
  return structs + records;
}

void trace_rays_path_gpu(MemoryPath path, Query query, const DeviceTrees& trees,
                         const RayF* rays, int count, MeshHit* hits) {
  if (count <= 0) return;
  with_path_kernel(path, query, &trees, [&](auto kernel, auto tree) {
    kernel<<<blocks_to_cover(count, k_block), k_block>>>(tree, rays, count, hits);
  });
  RT_CUDA_CHECK_LAUNCH("path_trace_kernel");
}

void trace_rays_path_cpu(MemoryPath path, Query query, const Bvh& bvh, const PackedBvh& packed,
                         std::span<const RayF> rays, std::span<MeshHit> hits) {
  check_runs_on(path, Backend::cpu);
  if (hits.size() != rays.size()) throw Error("trace_rays_path_cpu: one hit per ray");
  if (path == MemoryPath::global) {
    ch07::trace_rays_cpu(query, k_variant, bvh.view(), rays, hits);
    return;
  }
  const PackedTree<GlobalRecords> tree = host_view(packed);
  ch07::for_each_ray_cpu(rays.size(), [&](std::size_t i) {
    const ch07::TraceHit hit = query == Query::closest
                                   ? ch07::trace_bvh<Query::closest, k_variant>(tree, rays[i])
                                   : ch07::trace_bvh<Query::any, k_variant>(tree, rays[i]);
    hits[i] = {hit.t, hit.triangle};
  });
}

int path_kernel_registers(MemoryPath path, Query query) {
  int registers = 0;
  with_path_kernel(path, query, nullptr,
                   [&](auto kernel, auto) { registers = kernel_registers(kernel); });
  return registers;
}

const char* to_string(ConstantsIn where) {
  return where == ConstantsIn::parameters ? "kernel parameters" : "__constant__ memory";
}

CameraTrace::CameraTrace(const DeviceTrees& trees, const ch07::PinholeCamera& camera,
                         ConstantsIn where)
    : tree_(trees.kept()), camera_(camera), where_(where) {
  if (where_ == ConstantsIn::constant_memory) {
    const CameraTraceArgs args{camera_, tree_};
    RT_CUDA_CHECK(cudaMemcpyToSymbol(c_camera_trace, &args, sizeof args));
    g_constant_owner = this;
  }
}

void CameraTrace::launch(MeshHit* hits) const {
  const int count = camera_.width * camera_.height;
  if (count <= 0) return;
  const int blocks = blocks_to_cover(count, k_block);
  if (where_ == ConstantsIn::parameters) {
    camera_trace_kernel_parameters<<<blocks, k_block>>>({camera_, tree_}, hits);
  } else {
    // One __constant__ symbol per program: a later CameraTrace may have refilled it.
    if (g_constant_owner.load() != this)
      throw Error("CameraTrace: another CameraTrace has since filled the __constant__ symbol");
    camera_trace_kernel_constant<<<blocks, k_block>>>(hits);
  }
  RT_CUDA_CHECK_LAUNCH("camera_trace_kernel");
}

int CameraTrace::registers() const {
  return where_ == ConstantsIn::parameters ? kernel_registers(camera_trace_kernel_parameters)
                                           : kernel_registers(camera_trace_kernel_constant);
}

} // namespace rt::ch08
