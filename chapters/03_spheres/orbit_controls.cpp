// Chapter 03: camera controls for the window. See orbit_controls.h.
#include "orbit_controls.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <SDL.h>

#include "camera_cli.h"
#include "rt/error.h"

namespace rt::ch03 {
namespace {

constexpr double k_radians_per_pixel = 0.005;
constexpr double k_pan_per_pixel = 0.0015; // of the distance to the target
constexpr double k_zoom_per_step = 0.9;
constexpr double k_move_per_second = 0.8; // of the distance to the target

Vec3d unit(Vec3d v) { return v / length(v); }

} // namespace

void OrbitControls::handle(const SDL_Event& event) {
  switch (event.type) {
  case SDL_MOUSEBUTTONDOWN:
  case SDL_MOUSEBUTTONUP: {
    const bool down = event.type == SDL_MOUSEBUTTONDOWN;
    if (event.button.button == SDL_BUTTON_LEFT) orbiting_ = down;
    if (event.button.button == SDL_BUTTON_RIGHT || event.button.button == SDL_BUTTON_MIDDLE)
      panning_ = down;
    break;
  }
  case SDL_MOUSEMOTION:
    if (orbiting_) orbit(event.motion.xrel, event.motion.yrel);
    if (panning_) pan(event.motion.xrel, event.motion.yrel);
    break;
  case SDL_MOUSEWHEEL:
    zoom(event.wheel.y);
    break;
  case SDL_KEYDOWN:
    if (event.key.keysym.sym == SDLK_r) camera_ = home_;
    break;
  default:
    break;
  }
}

void OrbitControls::update(double seconds) {
  const Uint8* keys = SDL_GetKeyboardState(nullptr);
  const Vec3d forward = unit(camera_.target - camera_.eye);
  const Vec3d right = unit(cross(forward, camera_.up));
  const Vec3d up = unit(camera_.up);
  const double step = k_move_per_second * seconds * length(camera_.target - camera_.eye);
  if (keys[SDL_SCANCODE_W]) move(forward, step);
  if (keys[SDL_SCANCODE_S]) move(forward, -step);
  if (keys[SDL_SCANCODE_D]) move(right, step);
  if (keys[SDL_SCANCODE_A]) move(right, -step);
  if (keys[SDL_SCANCODE_E]) move(up, step);
  if (keys[SDL_SCANCODE_Q]) move(up, -step);
}

// The eye moves on a sphere around the target: yaw about the up axis, pitch towards it,
// stopping short of the poles where "up" would no longer say which way is up.
void OrbitControls::orbit(double dx_pixels, double dy_pixels) {
  const Vec3d up = unit(camera_.up);
  const Vec3d offset = camera_.eye - camera_.target;
  const double radius = length(offset);
  const Vec3d side = unit(cross(up, offset)); // horizontal, perpendicular to offset
  const Vec3d ahead = unit(cross(side, up));  // horizontal, towards the eye
  double yaw = std::atan2(dot(offset, side), dot(offset, ahead));
  double pitch = std::asin(std::clamp(dot(offset, up) / radius, -1.0, 1.0));
  yaw -= dx_pixels * k_radians_per_pixel;
  const double limit = 89.0 * std::numbers::pi / 180.0;
  pitch = std::clamp(pitch + dy_pixels * k_radians_per_pixel, -limit, limit);
  const Vec3d horizontal = ahead * std::cos(yaw) + side * std::sin(yaw);
  CameraSpec next = camera_;
  next.eye = camera_.target + (horizontal * std::cos(pitch) + up * std::sin(pitch)) * radius;
  move_to(next);
}

void OrbitControls::pan(double dx_pixels, double dy_pixels) {
  const Vec3d forward = unit(camera_.target - camera_.eye);
  const Vec3d right = unit(cross(forward, camera_.up));
  const Vec3d up = cross(right, forward);
  const double scale = k_pan_per_pixel * length(camera_.target - camera_.eye);
  const Vec3d shift = right * (-dx_pixels * scale) + up * (dy_pixels * scale);
  CameraSpec next = camera_;
  next.eye += shift;
  next.target += shift;
  move_to(next);
}

void OrbitControls::zoom(double steps) {
  const Vec3d offset = camera_.eye - camera_.target;
  CameraSpec next = camera_;
  next.eye = camera_.target + offset * std::pow(k_zoom_per_step, steps);
  move_to(next);
}

void OrbitControls::move(Vec3d along, double distance) {
  CameraSpec next = camera_;
  next.eye += along * distance;
  next.target += along * distance;
  move_to(next);
}

void OrbitControls::move_to(const CameraSpec& next) {
  try {
    validate_camera(next);
    camera_ = next;
  } catch (const UsageError&) {
    // Stays: the reader sees the camera stop at the edge of what it can show.
  }
}

} // namespace rt::ch03
