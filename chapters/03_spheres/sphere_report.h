// Chapter 03: the headless report's rows. The textbook and the stable ray/sphere intersection
// on each backend, each timed and compared with the float64 reference of the same camera.
#pragma once

#include "camera_spec.h"
#include "rt/backend.h"
#include "rt/launch.h"
#include "rt/report.h"
#include "scene.h"

namespace rt::ch03 {

// Rows for both variants on `backend` (and the CPU after the GPU), then the reference's row.
void report_sphere_variants(Backend backend, const SphereScene<float>& scene,
                            const CameraSpec& spec, Extent extent, int max_depth, int frames,
                            Report& report);

} // namespace rt::ch03
