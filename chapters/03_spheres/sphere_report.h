// Chapter 03: the headless report's rows. The textbook and the stable ray/sphere intersection
// on each backend, each timed and compared with the float64 reference of the same camera.
#pragma once

#include "camera_spec.h"
#include "rt/backend.h"
#include "rt/launch.h"
#include "rt/report.h"
#include "scene.h"
#include "trace.h"

namespace rt::ch03 {

// Rows for both variants on `backend` (and the CPU after the GPU), then the reference's row.
// `settings` gives the mirror depth and the spawn offset; each row sets its own variant. The
// throughput counts every ray a frame traced, mirror rays included.
void report_sphere_variants(Backend backend, const SphereScene<float>& scene,
                            const CameraSpec& spec, Extent extent, TraceSettings settings,
                            int frames, Report& report);

} // namespace rt::ch03
