// Chapter 07: the benchmark protocol on the host: views, the camera with its checks, and the
// CPU batches of rays. See protocol.h.
#include "protocol.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>

#include "camera_spec.h"
#include "rt/error.h"
#include "rt/report.h"
#include "supported_range.h"

namespace rt::ch07 {

const char* to_string(ViewKind kind) {
  switch (kind) {
  case ViewKind::auto_frame:
    return "auto-frame";
  case ViewKind::conference:
    return "conference";
  case ViewKind::sponza:
    return "sponza";
  case ViewKind::custom:
    return "custom";
  }
  return "unknown";
}

const char* to_string(RayType type) {
  switch (type) {
  case RayType::primary:
    return "primary";
  case RayType::ao:
    return "ao";
  case RayType::diffuse:
    return "diffuse";
  }
  return "unknown";
}

float scene_radius(const Aabb& bounds) {
  if (bounds.empty()) return 0.0f;
  const Vec3d extent = bounds.hi.as<double>() - bounds.lo.as<double>();
  return static_cast<float>(0.5 * std::sqrt(dot(extent, extent)));
}

ProtocolView auto_frame_view(const Aabb& bounds) {
  const float r = scene_radius(bounds);
  if (bounds.empty()) throw InputError("auto-frame: the scene has no triangles");
  if (!std::isfinite(r)) throw InputError("auto-frame: the scene's bounding box is not finite");
  if (!(r > 0.0f)) throw InputError("auto-frame: the scene is a single point");
  constexpr double k_vfov_degrees = 45.0;
  const double half_vfov = k_vfov_degrees * std::numbers::pi / 360.0;
  // In double from the float box, rounded once: the eye is as exact as the box allows.
  const Vec3d centre = (bounds.lo.as<double>() + bounds.hi.as<double>()) * 0.5;
  const Vec3d eye =
      centre + Vec3d{0.0, 0.0, 1.0} * (static_cast<double>(r) / std::sin(half_vfov));
  if (max_component(elementwise_abs(eye)) > ch03::k_max_coordinate)
    throw InputError("auto-frame: a camera that frames the scene (radius " +
                     format_scientific(r, 2) + ") would stand at " +
                     format_scientific(max_component(elementwise_abs(eye)), 2) +
                     " from the origin, beyond the supported +-" +
                     format_scientific(ch03::k_max_coordinate, 0));
  return {eye.as<float>(), centre.as<float>(), static_cast<float>(k_vfov_degrees),
          ViewKind::auto_frame};
}

std::optional<ProtocolView> interior_view(const std::string& scene_path) {
  std::string name = std::filesystem::path(scene_path).filename().string();
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (name.starts_with("conference"))
    return ProtocolView{
        {-300.0f, 400.0f, 300.0f}, {1000.0f, 100.0f, -700.0f}, 60.0f, ViewKind::conference};
  if (name.starts_with("sponza"))
    return ProtocolView{{-14.0f, 3.0f, 0.0f}, {10.0f, 5.0f, 0.0f}, 60.0f, ViewKind::sponza};
  return std::nullopt;
}

ProtocolView protocol_view(const std::string& scene_path, const Aabb& bounds) {
  if (const std::optional<ProtocolView> view = interior_view(scene_path)) return *view;
  return auto_frame_view(bounds);
}

namespace {

bool all_finite(Vec3f v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

} // namespace

PinholeCamera make_protocol_camera(Vec3f eye, Vec3f target, float vfov_degrees, int width,
                                   int height) {
  if (!all_finite(eye) || !all_finite(target))
    throw InputError("camera: eye and target must be finite");
  const double farthest = std::max(max_component(elementwise_abs(eye.as<double>())),
                                   max_component(elementwise_abs(target.as<double>())));
  if (farthest > ch03::k_max_coordinate)
    throw InputError("camera: eye and target must lie within +-" +
                     format_scientific(ch03::k_max_coordinate, 0) + " (a coordinate is " +
                     format_scientific(farthest, 2) + ")");
  if (eye == target) throw InputError("camera: eye and target are the same point");
  const double distance = length(target.as<double>() - eye.as<double>());
  if (distance < ch03::k_min_length)
    throw InputError("camera: eye and target are " + format_scientific(distance, 2) +
                     " apart; the shortest supported distance is " +
                     format_scientific(ch03::k_min_length, 0));
  if (!(vfov_degrees > 0.0f && vfov_degrees < 180.0f))
    throw InputError("camera: the field of view must lie between 0 and 180 degrees");
  if (width < 1 || width > k_max_image_side || height < 1 || height > k_max_image_side)
    throw InputError("camera: image size " + std::to_string(width) + "x" +
                     std::to_string(height) + " is outside 1.." +
                     std::to_string(k_max_image_side) + " pixels per side");
  ch03::CameraSpec spec;
  spec.eye = eye.as<double>();
  spec.target = target.as<double>();
  spec.fov_degrees = vfov_degrees;
  try {
    ch03::check_pixel_spacing(spec, {width, height});
  } catch (const UsageError& narrow) {
    throw InputError(std::string("camera: ") + narrow.what());
  }
  const PinholeCamera camera = ch03::make_pinhole_camera(eye, target, Vec3f{0.0f, 1.0f, 0.0f},
                                                         vfov_degrees, width, height);
  // A view straight up or down has no right direction: cross(forward, up) is zero, and its
  // normalisation NaN. (Eye and target within the supported range cannot overflow.)
  const ch03::ViewBasis<float>& basis = camera.basis;
  if (!all_finite(basis.forward) || !all_finite(basis.right) || !all_finite(basis.up))
    throw InputError("camera: the view direction is parallel to up (0, 1, 0)");
  if (!std::isfinite(camera.tan_half_vfov))
    throw InputError("camera: the field of view is too close to 180 degrees");
  return camera;
}

PinholeCamera make_protocol_camera(const ProtocolView& view, int width, int height) {
  return make_protocol_camera(view.eye, view.target, view.vfov_degrees, width, height);
}

std::vector<RayF> camera_rays_cpu(const PinholeCamera& camera) {
  std::vector<RayF> rays;
  rays.reserve(static_cast<std::size_t>(camera.width) * camera.height);
  for (int j = 0; j < camera.height; ++j)
    for (int i = 0; i < camera.width; ++i) rays.push_back(camera_ray(camera, i, j));
  return rays;
}

SecondaryRays secondary_rays_cpu(RayType type, const ch04::Mesh& mesh,
                                 std::span<const MeshHit> primary_hits,
                                 const PinholeCamera& camera, float scene_radius) {
  if (type == RayType::primary)
    throw Error("secondary_rays_cpu: primary rays come from the camera, not from hits");
  const long long pixel_count = static_cast<long long>(camera.width) * camera.height;
  if (static_cast<long long>(primary_hits.size()) != pixel_count)
    throw Error("secondary_rays_cpu: " + std::to_string(primary_hits.size()) +
                " primary hits for " + std::to_string(pixel_count) + " pixels");
  const long long triangle_count = static_cast<long long>(mesh.triangles.size());
  SecondaryRays out;
  for (int p = 0; p < static_cast<int>(pixel_count); ++p) {
    const MeshHit& hit = primary_hits[p];
    if (hit.triangle < 0) continue; // a miss: no secondary ray
    if (hit.triangle >= triangle_count)
      throw Error("secondary_rays_cpu: pixel " + std::to_string(p) + " hit triangle " +
                  std::to_string(hit.triangle) + " of a mesh of " +
                  std::to_string(triangle_count));
    const int i = p % camera.width, j = p / camera.width;
    out.rays.push_back(secondary_ray(type, camera_ray(camera, i, j), hit,
                                     mesh.triangle(hit.triangle), i, j, scene_radius));
    out.pixel.push_back(p);
  }
  return out;
}

std::vector<MeshHit> scatter_to_pixels(std::span<const MeshHit> hits,
                                       std::span<const int> pixel, int pixel_count) {
  if (hits.size() != pixel.size())
    throw Error("scatter_to_pixels: " + std::to_string(hits.size()) + " hits for " +
                std::to_string(pixel.size()) + " pixels");
  std::vector<MeshHit> image(static_cast<std::size_t>(std::max(pixel_count, 0)));
  for (std::size_t k = 0; k < hits.size(); ++k) {
    if (pixel[k] < 0 || pixel[k] >= pixel_count)
      throw Error("scatter_to_pixels: pixel " + std::to_string(pixel[k]) + " outside 0.." +
                  std::to_string(pixel_count - 1));
    image[pixel[k]] = hits[k];
  }
  return image;
}

} // namespace rt::ch07
