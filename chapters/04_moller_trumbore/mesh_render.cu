// Chapter 04: rendering a triangle scene. See mesh_render.h.
#include "mesh_render.h"

#include <limits>
#include <span>
#include <sstream>

#include "rt/error.h"
#include "trace.h"

namespace rt::ch04 {
namespace {

RT_HD inline Vec3f object_colour(int object) {
  switch (object) {
  case 0:
    return {0.85f, 0.3f, 0.25f}; // the icosphere
  case 1:
    return {0.25f, 0.45f, 0.85f}; // the box
  default:
    return {0.75f, 0.75f, 0.7f}; // the floor
  }
}

// Facing-ratio shading as in chapter 03, two-sided: a triangle seen from behind is lit like
// its front.
template <class T>
RT_HD Vec3<T> shade(const NearestTriangle<T>& hit, int object, Vec3<T> direction) {
  const Vec3<T> d = normalize(direction);
  if (hit.index < 0) return ch03::sky_colour(d);
  const T facing = absolute(dot(unit_normal(hit.normal), d));
  return object_colour(object).as<T>() * (T(0.25) + T(0.75) * facing);
}

} // namespace

TriangleScene make_demo_scene(int sphere_subdivisions, Vec3d offset) {
  TriangleScene scene;
  auto append = [&](const Mesh& part, int object) {
    const int base = static_cast<int>(scene.mesh.vertices.size());
    scene.mesh.vertices.insert(scene.mesh.vertices.end(), part.vertices.begin(),
                               part.vertices.end());
    for (const IndexedTriangle& t : part.triangles) {
      scene.mesh.triangles.push_back({t.v0 + base, t.v1 + base, t.v2 + base});
      scene.object.push_back(object);
    }
  };
  append(make_icosphere(sphere_subdivisions, offset + Vec3d{-1.2, 1.0, 0.0}, 1.0), 0);
  append(make_box(offset + Vec3d{0.6, 0.0, -0.8}, offset + Vec3d{2.2, 1.6, 0.8}, 2), 1);
  Mesh floor; // a quad: two triangles sharing a diagonal
  for (const Vec3d corner :
       {Vec3d{-6, 0, -6}, Vec3d{6, 0, -6}, Vec3d{6, 0, 6}, Vec3d{-6, 0, 6}})
    floor.vertices.push_back((offset + corner).as<float>());
  floor.triangles = {{0, 2, 1}, {0, 3, 2}};
  append(floor, 2);
  std::ostringstream moved;
  moved.precision(3);
  moved << "the scene moved by (" << offset.x << ", " << offset.y << ", " << offset.z << ")";
  check_supported_range(scene.mesh, moved.str());
  return scene;
}

DeviceTriangleScene::DeviceTriangleScene(const TriangleScene& scene)
    : vertices_(std::span<const Vec3f>(scene.mesh.vertices)),
      triangles_(std::span<const IndexedTriangle>(scene.mesh.triangles)),
      object_(std::span<const std::int32_t>(scene.object)) {}

MeshView DeviceTriangleScene::view() const {
  return {vertices_.data(), triangles_.data(), static_cast<int>(triangles_.size())};
}

// [listing:render_triangles]
void render_triangles(Backend backend, TriangleVariant variant, MeshView mesh,
                      const std::int32_t* object, const ch03::Camera<float>& camera,
                      Extent extent, Rgba8* pixels, MeshPixelRecord* records) {
  const int width = extent.width;
  for_each_pixel(backend, extent, [=] RT_HD(int x, int y) {
    const RayF ray = camera.ray_through_pixel(x, y);
    const NearestTriangle<float> hit = nearest_triangle(variant, mesh, ray);
    const Vec3f colour = shade(hit, hit.index < 0 ? -1 : object[hit.index], ray.direction);
    pixels[y * width + x] = ch03::to_rgba8(colour);
    if (records != nullptr)
      records[y * width + x] = {hit.t, hit.index, ch03::has_nan(colour) ? 1 : 0};
  });
}
// [/listing:render_triangles]

MeshReference render_triangles_reference(const TriangleScene& scene, const CameraSpec& spec,
                                         Extent extent) {
  const MeshView mesh = host_view(scene.mesh);
  const ch03::FloatRaysInDouble camera{ch03::make_camera<float>(spec, extent)};
  MeshReference reference{Image(extent.width, extent.height),
                          std::vector<int>(extent.pixel_count())};
  for_each_pixel_cpu(extent, [&](int x, int y) {
    const Ray<double> ray = camera.ray_through_pixel(x, y);
    const NearestTriangle<double> hit =
        nearest_triangle(TriangleVariant::watertight, mesh, ray);
    const std::size_t index = static_cast<std::size_t>(y) * extent.width + x;
    reference.image.pixels[index] =
        ch03::to_rgba8(shade(hit, hit.index < 0 ? -1 : scene.object[hit.index], ray.direction));
    reference.triangle[index] = hit.index;
  });
  return reference;
}

MeshFrameError compare_with_reference(const Image& image,
                                      const std::vector<MeshPixelRecord>& records,
                                      const MeshReference& reference) {
  if (image.pixels.size() != reference.image.pixels.size() ||
      records.size() != reference.triangle.size())
    throw Error("compare_with_reference: the frame and its reference differ in size");
  MeshFrameError error;
  error.pixels_differing =
      static_cast<long long>(count_differing_pixels(image.pixels, reference.image.pixels));
  for (std::size_t i = 0; i < records.size(); ++i) {
    error.nan_pixels += records[i].nan;
    if (records[i].triangle < 0 && reference.triangle[i] >= 0) ++error.holes;
  }
  return error;
}

} // namespace rt::ch04
