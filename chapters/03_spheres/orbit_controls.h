// Chapter 03: steering the camera in the window. The mouse orbits around the target (left
// button), pans (right or middle button) and zooms (wheel); W/A/S/D move forward, left, back
// and right, Q/E down and up; R returns to where the camera started.
#pragma once

#include "camera_spec.h"

union SDL_Event;

namespace rt::ch03 {

class OrbitControls {
public:
  explicit OrbitControls(const CameraSpec& start) : camera_(start), home_(start) {}

  // Mouse buttons, motion, wheel and the R key.
  void handle(const SDL_Event& event);
  // Held W/A/S/D/Q/E keys move the camera in proportion to the time since the last frame.
  void update(double seconds);

  const CameraSpec& camera() const { return camera_; }

private:
  void orbit(double dx_pixels, double dy_pixels);
  void pan(double dx_pixels, double dy_pixels);
  void zoom(double steps);
  void move(Vec3d along, double distance); // eye and target together
  // Takes `next` if validate_camera accepts it, else keeps the camera where it is: a wheel
  // turned on and on would bring the eye onto the target in float, or carry the camera
  // beyond the supported range (supported_range.h).
  void move_to(const CameraSpec& next);

  CameraSpec camera_;
  CameraSpec home_;
  bool orbiting_ = false;
  bool panning_ = false;
};

} // namespace rt::ch03
