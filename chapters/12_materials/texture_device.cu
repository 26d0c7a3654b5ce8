// Chapter 12: textures on the GPU. Each image's levels go into a CUDA mipmapped array, and a
// texture object per filter reads it through the texture unit; a plain copy of the texels
// serves the software filter. See textures.h. Compiled with -fmad=false (CMakeLists.txt): the
// software filter here fuses no a * b + c, as the CPU's does not, so the two agree bit for bit.
#include "textures.h"

#include <atomic>
#include <utility>

#include "rt/backend.h"
#include "rt/cuda_check.h"
#include "rt/device_buffer.h"
#include "rt/error.h"
#include "rt/launch.h"

namespace rt::ch12 {
namespace {

std::atomic<long long> g_live_arrays{0};
std::atomic<long long> g_live_objects{0};

template <class T> T* device_copy(const T* host, std::size_t count) {
  T* device = nullptr;
  if (count == 0) return device;
  RT_CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&device), count * sizeof(T)));
  const cudaError_t copied =
      cudaMemcpy(device, host, count * sizeof(T), cudaMemcpyHostToDevice);
  if (copied != cudaSuccess) cudaFree(device); // freed here: the caller never saw it
  RT_CUDA_CHECK(copied);
  return device;
}

// [listing:texture_object_for_filter]
// The texture unit's settings for one filter. All three wrap (glTF's "repeat") and take
// coordinates in [0, 1] (normalizedCoords). Point reads the bytes themselves, decoded by the
// kernel through the course's table so that the texel is the CPU's to the bit; bilinear and
// trilinear read floats, sRGB-decoded by the texture unit before it filters, as the software
// filter decodes first.
cudaTextureDesc texture_description(TextureFilter filter, bool srgb, int levels) {
  cudaTextureDesc description{};
  description.addressMode[0] = cudaAddressModeWrap;
  description.addressMode[1] = cudaAddressModeWrap;
  description.normalizedCoords = 1;
  if (filter == TextureFilter::point) {
    description.filterMode = cudaFilterModePoint;
    description.readMode = cudaReadModeElementType; // uchar4, as stored
    return description;
  }
  description.filterMode = cudaFilterModeLinear;
  description.readMode = cudaReadModeNormalizedFloat; // byte c reads c / 255
  description.sRGB = srgb ? 1 : 0;
  if (filter == TextureFilter::trilinear) {
    description.mipmapFilterMode = cudaFilterModeLinear; // blend the two nearest levels
    description.minMipmapLevelClamp = 0.0f;
    description.maxMipmapLevelClamp = static_cast<float>(levels - 1);
  }
  return description;
}
// [/listing:texture_object_for_filter]

__global__ void sample_textures_kernel(TextureTable table, const TextureQuery* queries,
                                       int count, Vec4f* results) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= count) return;
  const TextureQuery query = queries[i];
  results[i] = sample_texture(table, query.index, query.uv, query.lod);
}

} // namespace

// [listing:device_textures]
DeviceTextures::DeviceTextures(std::span<const TextureImage> images) {
  try {
    count_ = static_cast<int>(images.size());
    if (images.empty()) return;
    d_decode_ = device_copy(texel_decode_table().data(), texel_decode_table().size());

    // The software path: every image's levels end to end, and views into them.
    std::size_t total = 0;
    for (const TextureImage& image : images) total += image.texels.size();
    RT_CUDA_CHECK(cudaMalloc(reinterpret_cast<void**>(&d_texels_), total * sizeof(Rgba8)));
    std::vector<TextureView> views;
    std::size_t start = 0;
    for (const TextureImage& image : images) {
      RT_CUDA_CHECK(cudaMemcpy(d_texels_ + start, image.texels.data(),
                               image.texels.size() * sizeof(Rgba8), cudaMemcpyHostToDevice));
      views.push_back(view_of(image, d_texels_ + start));
      start += image.texels.size();
    }
    d_views_ = device_copy(views.data(), views.size());

    // The texture unit's path: a mipmapped array of uchar4 per image, each level copied in.
    const cudaChannelFormatDesc channels = cudaCreateChannelDesc<uchar4>();
    for (const TextureImage& image : images) {
      cudaMipmappedArray_t array = nullptr;
      const cudaExtent extent = make_cudaExtent(image.width, image.height, 0); // depth 0: 2D
      RT_CUDA_CHECK(cudaMallocMipmappedArray(&array, &channels, extent,
                                             static_cast<unsigned>(image.level_count())));
      arrays_.push_back(array);
      ++g_live_arrays;
      for (int level = 0; level < image.level_count(); ++level) {
        const TextureLevel& size = image.levels[level];
        cudaArray_t level_array = nullptr;
        RT_CUDA_CHECK(cudaGetMipmappedArrayLevel(&level_array, array, level));
        const std::size_t row = static_cast<std::size_t>(size.width) * sizeof(Rgba8);
        RT_CUDA_CHECK(cudaMemcpy2DToArray(level_array, 0, 0, image.texels.data() + size.offset,
                                          row, row, size.height, cudaMemcpyHostToDevice));
      }
      // Point and bilinear read level 0 alone (an array of its own); trilinear all levels.
      cudaArray_t level0 = nullptr;
      RT_CUDA_CHECK(cudaGetMipmappedArrayLevel(&level0, array, 0));
      for (const TextureFilter filter :
           {TextureFilter::point, TextureFilter::bilinear, TextureFilter::trilinear}) {
        cudaResourceDesc resource{};
        if (filter == TextureFilter::trilinear) {
          resource.resType = cudaResourceTypeMipmappedArray;
          resource.res.mipmap.mipmap = array;
        } else {
          resource.resType = cudaResourceTypeArray;
          resource.res.array.array = level0;
        }
        const cudaTextureDesc description =
            texture_description(filter, image.srgb, image.level_count());
        cudaTextureObject_t object = 0;
        RT_CUDA_CHECK(cudaCreateTextureObject(&object, &resource, &description, nullptr));
        objects_[static_cast<int>(filter)].push_back(object);
        ++g_live_objects;
      }
    }
    for (int filter = 0; filter < 3; ++filter) {
      d_objects_[filter] = device_copy(objects_[filter].data(), objects_[filter].size());
    }
  } catch (...) {
    release(); // what was made before the failure, then the error goes on
    throw;
  }
}
// [/listing:device_textures]

DeviceTextures::~DeviceTextures() { release(); }

DeviceTextures::DeviceTextures(DeviceTextures&& other) noexcept { *this = std::move(other); }

DeviceTextures& DeviceTextures::operator=(DeviceTextures&& other) noexcept {
  if (this == &other) return *this;
  release();
  count_ = std::exchange(other.count_, 0);
  arrays_ = std::exchange(other.arrays_, {});
  for (int filter = 0; filter < 3; ++filter) {
    objects_[filter] = std::exchange(other.objects_[filter], {});
    d_objects_[filter] = std::exchange(other.d_objects_[filter], nullptr);
  }
  d_texels_ = std::exchange(other.d_texels_, nullptr);
  d_views_ = std::exchange(other.d_views_, nullptr);
  d_decode_ = std::exchange(other.d_decode_, nullptr);
  return *this;
}

void DeviceTextures::release() noexcept {
  // Never throws from a destructor: the calls' errors are dropped, as DeviceBuffer's are.
  for (int filter = 0; filter < 3; ++filter) {
    for (const cudaTextureObject_t object : objects_[filter]) {
      cudaDestroyTextureObject(object);
      --g_live_objects;
    }
    objects_[filter].clear();
    if (d_objects_[filter] != nullptr) cudaFree(d_objects_[filter]);
    d_objects_[filter] = nullptr;
  }
  for (const cudaMipmappedArray_t array : arrays_) {
    cudaFreeMipmappedArray(array);
    --g_live_arrays;
  }
  arrays_.clear();
  // Only what was made: with no textures, no CUDA call at all (a machine without a GPU too).
  for (void* pointer : {static_cast<void*>(d_texels_), static_cast<void*>(d_views_),
                        static_cast<void*>(d_decode_)}) {
    if (pointer != nullptr) cudaFree(pointer);
  }
  d_texels_ = nullptr;
  d_views_ = nullptr;
  d_decode_ = nullptr;
  count_ = 0;
}

TextureTable DeviceTextures::table(TextureFilter filter, bool objects_on) const {
  TextureTable table;
  table.views = d_views_;
  table.objects = d_objects_[static_cast<int>(filter)];
  table.decode = d_decode_;
  table.count = count_;
  table.filter = filter;
  table.objects_on = objects_on;
  return table;
}

long long DeviceTextures::live_arrays() { return g_live_arrays.load(); }
long long DeviceTextures::live_objects() { return g_live_objects.load(); }

std::vector<Vec4f> sample_textures_on_gpu(const TextureTable& table,
                                          std::span<const TextureQuery> queries) {
  std::vector<Vec4f> results(queries.size());
  if (queries.empty()) return results;
  const DeviceBuffer<TextureQuery> d_queries(queries);
  DeviceBuffer<Vec4f> d_results(queries.size());
  const int count = static_cast<int>(queries.size());
  sample_textures_kernel<<<blocks_to_cover(count, k_index_block), k_index_block>>>(
      table, d_queries.data(), count, d_results.data());
  RT_CUDA_CHECK_LAUNCH("sample_textures_kernel");
  d_results.download(results);
  return results;
}

} // namespace rt::ch12
