// Chapter 04 test cases shared by the CPU and GPU tests: the camera the demo scene is checked
// through, above and in front of it, looking at its middle.
#pragma once

#include "camera_spec.h"

namespace rt::testing {

// `shift` moves the camera with a demo scene made at that offset.
inline ch03::CameraSpec demo_scene_camera(Vec3d shift = {}) {
  ch03::CameraSpec spec;
  spec.eye = Vec3d{0.0, 2.2, 6.5} + shift;
  spec.target = Vec3d{0.3, 0.7, 0.0} + shift;
  return spec;
}

} // namespace rt::testing
