// Chapter 05: a loaded model on screen. See model_render.h.
#include "model_render.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <type_traits>
#include <utility>

#include <cuda_runtime_api.h>

#include "rt/atomic.h"
#include "rt/cuda_check.h"
#include "rt/error.h"
#include "supported_range.h"
#include "trace.h"

namespace rt::ch05 {
namespace {

using ch04::MeshView;
using ch04::nearest_triangle;
using ch04::NearestTriangle;

// A colour per material id from a fixed palette (the first four fit the Cornell room's
// white, red, green and light); -1, a face without a material, is clay. The .mtl's own
// colours belong with the shading of the next chapter.
RT_HD inline Vec3f material_colour(int material) {
  if (material < 0) return {0.8f, 0.55f, 0.38f};
  switch (material % 8) {
  case 0:
    return {0.75f, 0.75f, 0.72f};
  case 1:
    return {0.75f, 0.18f, 0.14f};
  case 2:
    return {0.2f, 0.6f, 0.25f};
  case 3:
    return {1.0f, 0.93f, 0.75f};
  case 4:
    return {0.25f, 0.45f, 0.85f};
  case 5:
    return {0.85f, 0.7f, 0.2f};
  case 6:
    return {0.6f, 0.35f, 0.75f};
  default:
    return {0.2f, 0.65f, 0.7f};
  }
}

// Facing-ratio shading as in chapters 03 and 04, two-sided.
template <class T>
RT_HD Vec3<T> shade(const NearestTriangle<T>& hit, const std::int32_t* material,
                    Vec3<T> direction) {
  const Vec3<T> d = normalize(direction);
  if (hit.index < 0) return ch03::sky_colour(d);
  const T facing = absolute(dot(ch04::unit_normal(hit.normal), d));
  return material_colour(material[hit.index]).template as<T>() * (T(0.25) + T(0.75) * facing);
}

std::string gigabytes(std::size_t bytes) {
  std::ostringstream text;
  text.precision(3);
  text << static_cast<double>(bytes) / 1e9 << " GB";
  return text.str();
}

} // namespace

TriangleScene take_scene(ObjMesh& mesh) {
  static_assert(std::is_same_v<decltype(mesh.material_ids), std::vector<std::int32_t>>);
  return {std::move(mesh.geometry), std::move(mesh.material_ids)};
}

// [listing:frame_bounds]
CameraSpec frame_bounds(Vec3f bounds_min, Vec3f bounds_max, CameraSpec camera, Extent extent) {
  const Vec3d lo = bounds_min.as<double>(), hi = bounds_max.as<double>();
  const Vec3d centre = (lo + hi) * 0.5;
  double radius = 0.5 * length(hi - lo); // of the sphere around the box
  if (!(radius > 0.0)) radius = 1.0;     // a single point: any distance shows it
  // The narrower of the two fields of view decides: a wide image is limited by its height.
  const double half_vertical = camera.fov_degrees * std::numbers::pi / 360.0;
  const double half_horizontal =
      std::atan(std::tan(half_vertical) * double(extent.width) / extent.height);
  const double half_fov = std::min(half_vertical, half_horizontal);
  // At distance radius / sin(half_fov) the sphere touches the edges of the view cone.
  camera.target = centre;
  camera.eye = centre + normalize(k_framing_direction) * (radius / std::sin(half_fov));
  // The eye stands further out than the box: near the edge of the supported range it lies
  // beyond it, and a tiny box far from the origin can round to the same float as its centre.
  const double farthest = max_component(elementwise_abs(camera.eye));
  const bool too_far = !(farthest <= ch03::k_max_coordinate);
  if (too_far || camera.eye.as<float>() == camera.target.as<float>()) {
    std::ostringstream what;
    what.precision(3);
    what << "cannot frame the model: its bounding box (centre " << centre.x << "," << centre.y
         << "," << centre.z << ", radius " << radius << ") needs a camera ";
    if (too_far)
      what << farthest << " from the origin, beyond the supported +-" << ch03::k_max_coordinate;
    else
      what << "that float rounds onto its target";
    what << "; give --eye and --target";
    throw InputError(what.str());
  }
  return camera;
}
// [/listing:frame_bounds]

PixelSample sample_of(Extent image, long long max_pixels) {
  PixelSample sample{image, 1};
  while (sample.extent().pixel_count() > max_pixels &&
         sample.stride < std::max(image.width, image.height))
    ++sample.stride;
  return sample;
}

// [listing:render_model]
void render_model(Backend backend, TriangleVariant variant, MeshView mesh,
                  const std::int32_t* material, const ch03::Camera<float>& camera,
                  PixelSample sample, Rgba8* pixels, ch04::MeshPixelRecord* records,
                  unsigned* rows_done) {
  const int width = sample.extent().width;
  for_each_pixel(backend, sample.extent(), [=] RT_HD(int x, int y) {
    const ch03::RayF ray = camera.ray_through_pixel(sample.column(x), sample.row(y));
    const NearestTriangle<float> hit = nearest_triangle(variant, mesh, ray);
    const Vec3f colour = shade(hit, material, ray.direction);
    pixels[y * width + x] = ch03::to_rgba8(colour);
    if (records != nullptr)
      records[y * width + x] = {hit.t, hit.index, ch03::has_nan(colour) ? 1 : 0};
    // The CPU backend hands out whole rows, so a row's last pixel finishes its row.
    if (rows_done != nullptr && x == width - 1) atomic_increment(rows_done);
  });
}
// [/listing:render_model]

ch04::MeshReference render_model_reference(const TriangleScene& scene,
                                           const CameraSpec& camera_spec, PixelSample sample,
                                           unsigned* rows_done) {
  const MeshView mesh = ch04::host_view(scene.mesh);
  // The float camera's rays in double: the reference starts from the same rounded inputs.
  const ch03::FloatRaysInDouble camera{ch03::make_camera<float>(camera_spec, sample.image)};
  const Extent extent = sample.extent();
  ch04::MeshReference reference{Image(extent.width, extent.height),
                                std::vector<int>(extent.pixel_count())};
  for_each_pixel_cpu(extent, [&](int x, int y) {
    const ch03::Ray<double> ray = camera.ray_through_pixel(sample.column(x), sample.row(y));
    const NearestTriangle<double> hit =
        nearest_triangle(TriangleVariant::watertight, mesh, ray);
    const std::size_t index = static_cast<std::size_t>(y) * extent.width + x;
    reference.image.pixels[index] =
        ch03::to_rgba8(shade(hit, scene.object.data(), ray.direction));
    reference.triangle[index] = hit.index;
    if (rows_done != nullptr && x == extent.width - 1) atomic_increment(rows_done);
  });
  return reference;
}

std::size_t device_bytes_needed(const TriangleScene& scene, Extent image) {
  return scene.mesh.vertices.size() * sizeof(Vec3f) +
         scene.mesh.triangles.size() * sizeof(ch04::IndexedTriangle) +
         scene.object.size() * sizeof(std::int32_t) +
         static_cast<std::size_t>(image.pixel_count()) *
             (sizeof(Rgba8) + sizeof(ch04::MeshPixelRecord));
}

void check_device_memory(std::size_t bytes, const std::string& what) {
  std::size_t free_bytes = 0, total_bytes = 0;
  RT_CUDA_CHECK(cudaMemGetInfo(&free_bytes, &total_bytes));
  if (bytes > free_bytes)
    throw InputError(what + ": needs " + gigabytes(bytes) + " of GPU memory, " +
                     gigabytes(free_bytes) + " of " + gigabytes(total_bytes) + " are free");
}

} // namespace rt::ch05
