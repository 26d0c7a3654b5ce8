// Chapter 03: the camera flags every chapter from here on accepts:
//   --eye x,y,z  --target x,y,z  --up x,y,z  --fov degrees  --camera pinhole|orthographic
#pragma once

#include <CLI/CLI.hpp>

#include "camera_spec.h"

namespace rt::ch03 {

// Adds the flags to `app`; the values land in `spec` once the command line is parsed.
void add_camera_options(CLI::App& app, CameraSpec& spec);

// Throws UsageError when the settings describe no camera: eye on the target (also where only
// float rounds them together, or closer than k_min_length), up parallel to the view direction,
// a field of view outside (0, 180), anything not finite, an eye or target beyond
// k_max_coordinate (supported_range.h). make_camera() adds the checks that need the image size.
void validate_camera(const CameraSpec& spec);

} // namespace rt::ch03
