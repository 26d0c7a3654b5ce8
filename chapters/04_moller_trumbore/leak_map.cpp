// Chapter 04: the picture of where rays leak. See leak_map.h.
#include "leak_map.h"

#include <cmath>
#include <cstdint>
#include <vector>

#include "adversarial_rays.h"
#include "leak_configurations.h"
#include "mesh_render.h"

namespace rt::ch04 {
namespace {

// The pixel through which the pinhole camera sees p, and p's distance from the eye; false
// when p lies behind the camera or outside the image.
bool project(const ch03::PinholeCamera<float>& camera, Vec3f p, int& i, int& j,
             float& distance) {
  const Vec3f v = p - camera.eye;
  const float depth = dot(v, camera.basis.forward);
  if (!(depth > 0.0f)) return false;
  const float sx = dot(v, camera.basis.right) / (depth * camera.tan_half_vfov * camera.aspect);
  const float sy = dot(v, camera.basis.up) / (depth * camera.tan_half_vfov);
  i = static_cast<int>(std::floor((sx + 1.0f) * 0.5f * float(camera.width)));
  j = static_cast<int>(std::floor((1.0f - sy) * 0.5f * float(camera.height)));
  distance = length(v);
  return i >= 0 && i < camera.width && j >= 0 && j < camera.height;
}

// One mesh of the leak test, seen from outside, with its leaked rays' targets marked.
Image leak_panel(TriangleVariant variant, const LeakConfiguration& configuration, int ray_count,
                 Extent panel) {
  const Mesh mesh = configuration.make_mesh();
  const std::vector<AimedRay> aimed = aimed_rays(
      mesh, configuration.inside(), configuration.spread, ray_count, configuration.seed);
  std::vector<RayF> rays;
  rays.reserve(aimed.size());
  for (const AimedRay& a : aimed) rays.push_back(a.ray);
  const std::vector<HitTally> tallies = tally_hits_cpu(variant, mesh, rays);

  const Vec3d centre = configuration.offset;
  const CameraSpec spec{centre + Vec3d{2.0, 2.4, 4.2}, centre, {0, 1, 0}, 40.0};
  const ch03::Camera<float> camera = ch03::make_camera<float>(spec, panel);
  const std::vector<std::int32_t> grey(mesh.triangles.size(), 2); // the floor's colour
  Image image(panel.width, panel.height);
  std::vector<MeshPixelRecord> records(image.pixels.size());
  render_triangles(Backend::cpu, TriangleVariant::watertight, host_view(mesh), grey.data(),
                   camera, panel, image.pixels.data(), records.data());

  for (std::size_t r = 0; r < aimed.size(); ++r) {
    int i = 0, j = 0;
    float distance = 0.0f;
    if (tallies[r].hits != 0 || !project(camera.pinhole, aimed[r].target, i, j, distance))
      continue;
    // Only targets the camera sees: nothing nearer along the pixel's ray (1% of slack).
    if (records[j * panel.width + i].t < 0.99f * distance) continue;
    const Rgba8 mark = aimed[r].at_vertex ? Rgba8{255, 220, 0, 255} : Rgba8{220, 20, 20, 255};
    const int reach = aimed[r].at_vertex ? 2 : 0; // vertices as 5x5 squares
    for (int y = j - reach; y <= j + reach; ++y)
      for (int x = i - reach; x <= i + reach; ++x)
        if (x >= 0 && x < panel.width && y >= 0 && y < panel.height) image.at(x, y) = mark;
  }
  return image;
}

} // namespace

Image leak_map(TriangleVariant variant, int ray_count, Extent panel) {
  const Image sphere = leak_panel(variant, k_leak_configurations[0], ray_count, panel);
  const Image box = leak_panel(variant, k_leak_configurations[2], ray_count, panel);
  Image both(2 * panel.width, panel.height);
  for (int y = 0; y < panel.height; ++y)
    for (int x = 0; x < panel.width; ++x) {
      both.at(x, y) = sphere.at(x, y);
      both.at(panel.width + x, y) = box.at(x, y);
    }
  return both;
}

} // namespace rt::ch04
