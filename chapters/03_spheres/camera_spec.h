// Chapter 03: the camera as a reader sets it (eye, target, up, vertical field of view) and
// either kind of camera built from it. Every chapter from here on takes these settings from
// the command line with the same flags.
#pragma once

#include <cmath>
#include <numbers>

#include "camera.h"
#include "rt/launch.h"

namespace rt::ch03 {

enum class CameraKind { pinhole, orthographic };

struct CameraSpec {
  Vec3d eye{0.0, 1.5, 6.0};
  Vec3d target{0.0, 0.8, 0.0};
  Vec3d up{0.0, 1.0, 0.0};
  double fov_degrees = 40.0; // vertical field of view
  CameraKind kind = CameraKind::pinhole;
};

// Either camera behind one call. The orthographic one frames the plane through the target
// exactly as the pinhole one with the same settings does.
template <class T> struct Camera {
  CameraKind kind = CameraKind::pinhole;
  PinholeCamera<T> pinhole{};
  OrthographicCamera<T> orthographic{};

  RT_HD Ray<T> ray_through_pixel(int i, int j) const {
    return kind == CameraKind::pinhole ? pinhole.ray_through_pixel(i, j)
                                       : orthographic.ray_through_pixel(i, j);
  }
};

// The float camera's rays, converted exactly to double: a float64 reference traced with it
// differs from the float render only in the arithmetic after the camera.
struct FloatRaysInDouble {
  Camera<float> camera;
  RT_HD Ray<double> ray_through_pixel(int i, int j) const {
    return ray_as<double>(camera.ray_through_pixel(i, j));
  }
};

// Throws UsageError when neighbouring pixels of an image of `extent` would get the same ray,
// or rays less than a few float steps apart: a field of view too narrow for the image's
// height, or an orthographic view too small for its distance from the origin.
void check_pixel_spacing(const CameraSpec& spec, Extent extent);

// Throws what check_pixel_spacing throws.
template <class T> Camera<T> make_camera(const CameraSpec& spec, Extent extent) {
  check_pixel_spacing(spec, extent);
  Camera<T> camera;
  camera.kind = spec.kind;
  const Vec3<T> eye = spec.eye.as<T>(), target = spec.target.as<T>(), up = spec.up.as<T>();
  camera.pinhole = make_pinhole_camera(eye, target, up, static_cast<T>(spec.fov_degrees),
                                       extent.width, extent.height);
  const double half_fov = spec.fov_degrees * std::numbers::pi / 360.0;
  const double view_height = 2.0 * length(spec.target - spec.eye) * std::tan(half_fov);
  camera.orthographic = make_orthographic_camera(eye, target, up, static_cast<T>(view_height),
                                                 extent.width, extent.height);
  return camera;
}

} // namespace rt::ch03
