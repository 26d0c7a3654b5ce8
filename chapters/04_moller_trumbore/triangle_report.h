// Chapter 04: the headless report's rows. Moller-Trumbore and the watertight test render the
// scene on each backend against the float64 reference; then rays fired from inside closed
// meshes at their vertices and edges count how many slip out between the triangles.
#pragma once

#include "camera_spec.h"
#include "mesh_render.h"
#include "rt/backend.h"
#include "rt/launch.h"
#include "rt/report.h"

namespace rt::ch04 {

// The render rows of both variants on `backend` (and the CPU after the GPU), the reference's
// row, then the leak rows: `leak_rays` rays for each closed mesh and variant.
void report_triangle_variants(Backend backend, const TriangleScene& scene,
                              const CameraSpec& spec, Extent extent, int frames, int leak_rays,
                              Report& report);

} // namespace rt::ch04
