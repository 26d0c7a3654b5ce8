// Chapter 02: rendering one frame of the animation on either backend, and the pixel buffer
// shared between OpenGL and CUDA that lets the kernel write straight into what GL displays.
#pragma once

#include <GL/glew.h>
#include <cuda_runtime_api.h>

#include "animated_pattern.h"
#include "rt/backend.h"
#include "rt/image.h"
#include "rt/launch.h"

namespace rt::ch02 {

// One frame into `pixels`: device memory for Backend::gpu, host memory for Backend::cpu.
void render_frame(Backend backend, Rgba8* pixels, Extent extent, int frame);
// One frame as a host image (the CPU reference, or a GPU frame copied back).
Image render_frame_image(Backend backend, Extent extent, int frame);

// What a read of the pixel buffer while a kernel still writes it could return: each warp of
// the launch (32 threads: two rows of a 16x16 block) has written frame `frame` or not yet,
// and the pixels it has not reached still hold frame - 1. Which warps have finished is not
// fixed; the picture lets about half of them finish, chosen by a hash. Two panels: the torn
// frame, and its pixels that differ from frame `frame` in white (the rest dimmed).
Image torn_frame(Extent extent, int frame);

// A GL pixel buffer object (PBO) of `bytes` bytes, owned.
class GlPixelBuffer {
public:
  explicit GlPixelBuffer(std::size_t bytes);
  ~GlPixelBuffer();
  GlPixelBuffer(const GlPixelBuffer&) = delete;
  GlPixelBuffer& operator=(const GlPixelBuffer&) = delete;
  GLuint id() const { return id_; }
  std::size_t bytes() const { return bytes_; }

private:
  GLuint id_ = 0;         // GL buffer name
  std::size_t bytes_ = 0; // size of its storage
};

// [listing:registration]
// A GL buffer registered with CUDA. Registration is the expensive step (done once per buffer);
// mapping, done every frame, hands CUDA a device pointer into the buffer's storage. The
// destructor unregisters, which must happen before GL deletes the buffer: declare the
// registration after the buffer so that it is destroyed first.
class CudaGlRegistration {
public:
  explicit CudaGlRegistration(const GlPixelBuffer& buffer);
  ~CudaGlRegistration();
  CudaGlRegistration(const CudaGlRegistration&) = delete;
  CudaGlRegistration& operator=(const CudaGlRegistration&) = delete;

  // While a Mapping lives, CUDA owns the buffer and GL must not touch it.
  class Mapping {
  public:
    explicit Mapping(cudaGraphicsResource_t resource);
    ~Mapping(); // unmaps: GL may use the buffer again
    Mapping(const Mapping&) = delete;
    Mapping& operator=(const Mapping&) = delete;
    Rgba8* pixels() const { return pixels_; }

  private:
    cudaGraphicsResource_t resource_;
    Rgba8* pixels_ = nullptr;
  };
  Mapping map() const { return Mapping(resource_); }

private:
  cudaGraphicsResource_t resource_ = nullptr;
};
// [/listing:registration]

} // namespace rt::ch02
