// Chapter 05: a loaded model on screen. The camera frames the model's bounding box by itself;
// every ray tests every triangle (brute force) with either test of chapter 04, coloured by
// material; the float64 reference and the CPU rows trace a regular sample of the pixels,
// because brute force over 100 000 triangles costs the CPU milliseconds per ray.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "camera_spec.h"
#include "mesh_render.h"
#include "obj_loader.h"
#include "rt/backend.h"
#include "rt/image.h"
#include "rt/launch.h"
#include "triangles.h"

namespace rt::ch05 {

using ch03::CameraSpec;
using ch04::TriangleScene;
using ch04::TriangleVariant;

// The loaded mesh as chapter 04's scene: its triangles, with each one's material id as its
// "object" (what picks the colour). Moves the positions, triangles and material ids out of
// `mesh`; its other fields (bounds, normals, counts) stay.
TriangleScene take_scene(ObjMesh& mesh);

// Where the automatic camera stands, seen from the model: to the right, above and in front.
inline constexpr Vec3d k_framing_direction{1.0, 0.6, 1.4};

// `camera` with eye and target set so that the whole box is in view: it looks at the box's
// centre from k_framing_direction, far enough that the box's bounding sphere fits both the
// vertical and the horizontal field of view of an image of `extent`. Field of view, up and
// camera kind are kept. Throws InputError, naming the cause, if the eye would stand beyond
// chapter 03's k_max_coordinate (a box near the edge of the supported range) or round onto
// the target in float (a box too small to see at its distance from the origin).
CameraSpec frame_bounds(Vec3f bounds_min, Vec3f bounds_max, CameraSpec camera, Extent extent);

// Every stride-th pixel of every stride-th row of an image, from the middle of each
// stride x stride block: the pixels the float64 reference and the CPU rows trace.
struct PixelSample {
  Extent image;   // the camera's whole image
  int stride = 1; // 1: every pixel

  RT_HD int offset() const { return stride / 2; }
  RT_HD int column(int x) const { return x * stride + offset(); } // in the whole image
  RT_HD int row(int y) const { return y * stride + offset(); }
  Extent extent() const { // the sampled pixels, as an image of their own
    return {(image.width - offset() + stride - 1) / stride,
            (image.height - offset() + stride - 1) / stride};
  }
};

// The densest sample of `image` with at most max_pixels pixels (at least one pixel).
PixelSample sample_of(Extent image, long long max_pixels);

// The sampled pixels of a whole image's pixels (or records).
template <class T>
std::vector<T> sampled(const std::vector<T>& whole, const PixelSample& sample) {
  const Extent e = sample.extent();
  std::vector<T> out;
  out.reserve(static_cast<std::size_t>(e.pixel_count()));
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x)
      out.push_back(whole[static_cast<std::size_t>(sample.row(y)) * sample.image.width +
                          sample.column(x)]);
  return out;
}

// Renders the sample's pixels of the camera's image into pixels and records (laid out as an
// image of sample.extent(); records may be null): device memory on the GPU backend, with
// mesh and material there too; host memory on the CPU. rows_done, when not null (CPU backend
// only), counts finished rows for a progress line.
void render_model(Backend backend, TriangleVariant variant, ch04::MeshView mesh,
                  const std::int32_t* material, const ch03::Camera<float>& camera,
                  PixelSample sample, Rgba8* pixels, ch04::MeshPixelRecord* records = nullptr,
                  unsigned* rows_done = nullptr);

// The float64 reference of the sample: the watertight test in double on the float camera's
// rays, on CPU threads.
ch04::MeshReference render_model_reference(const TriangleScene& scene, const CameraSpec& camera,
                                           PixelSample sample, unsigned* rows_done = nullptr);

// Device memory the GPU rows need: the mesh (positions, triangles, material ids), and a frame
// of pixels and records of `image`.
std::size_t device_bytes_needed(const TriangleScene& scene, Extent image);

// Throws InputError, naming `what`, when the GPU has less free memory than `bytes` (asked with
// cudaMemGetInfo before anything is uploaded, so a model too large fails with one line
// instead of an allocation error halfway).
void check_device_memory(std::size_t bytes, const std::string& what);

} // namespace rt::ch05
