// Chapter 05: the report of a loaded model. Its context (what the model holds, how long it
// took to load, where the camera looks from), its brute-force renders against the float64
// reference, and the cost of brute force growing with the triangle count.
#pragma once

#include <optional>
#include <string>

#include "model_render.h"
#include "obj_loader.h"
#include "rt/backend.h"
#include "rt/image.h"
#include "rt/report.h"
#include "window_loop.h"

namespace rt::ch05 {

// Context lines: the scene file, what the model holds, its bounds, the load time and the
// camera (framed automatically, or from the flags).
void add_model_context(Report& report, const std::string& path, const ObjMesh& mesh,
                       double load_ms, const CameraSpec& camera, bool camera_from_flags);

// What the headless report measures.
struct ModelMeasurements {
  Extent extent;                  // the image
  bool size_from_backend = false; // neither --width nor --height given: the backend's default
  long long reference_pixels = 0; // the most pixels the reference and the CPU rows trace
  int scaling_max = 0;            // icospheres of 20 * 4^k triangles, k = 0..this; -1: none
  Vec3d centre;                   // ... placed where the model is
  double radius = 0;
  TriangleVariant image_variant = TriangleVariant::watertight;
  int frames = 0;         // --frames
  std::string scene_path; // named when the GPU's memory is too small for it
};

// The headless report: context lines, then both variants' renders on `backend` (the CPU's on a
// sample of the pixels) against the reference, then the brute-force rows. Returns the whole
// image in the image's variant when one of the measured frames is it.
std::optional<Image> report_model(Backend backend, const TriangleScene& scene,
                                  const CameraSpec& spec, const ModelMeasurements& m,
                                  Report& report);

// The whole image on the CPU, untimed, with a progress line, for --output when the CPU rows
// traced a sample only.
Image render_image_on_cpu(const TriangleScene& scene, const CameraSpec& spec, Extent extent,
                          TriangleVariant variant);

// The window's row: the last frame on screen against the float64 reference of its camera, on
// a sample of at most `reference_pixels` pixels.
ReportRow sampled_window_row(const ch03::WindowResult& shown, Backend backend,
                             const TriangleScene& scene, TriangleVariant variant,
                             long long reference_pixels);

} // namespace rt::ch05
