// Chapter 11: the program's two reports. The kernels' rows (time per sample and whether each
// gives the same sums as the specialised megakernel), and the error against run time of every
// strategy and variant against a float64 reference.
#pragma once

#include "convergence.h"
#include "path_render.h"
#include "rt/backend.h"
#include "rt/report.h"

namespace rt::ch11 {

// The specialised megakernel, the all-features megakernel and the specialised wavefront, each
// timed over `frames` passes of one sample per pixel (0: the protocol's count) from a fresh
// start, so that each ends with the same samples: their sums are compared bit for bit.
void add_kernel_rows(PathRenderer& renderer, Strategy strategy, const CameraSpec& camera,
                     Extent extent, int frames, Report& report);

// --moving: `frames` frames of chapter 10's moving scene (60 for 0), each its vertices moved,
// its tree built again on the backend and one sample per pixel by `settings`; the row gives the
// mean wall time of the two parts.
void add_moving_rows(PathRenderer& renderer, const RenderSettings& settings, int detail,
                     const CameraSpec& camera, Extent extent, int frames, Report& report);

// The frames the moving scene is run for: `frames`, or 60 for 0.
inline int moving_frame_count(int frames) { return frames > 0 ? frames : 60; }

// --convergence: a reference of `reference_samples`, then the megakernel with each strategy
// and the wavefront with MIS at 1, 2, 4, ... max_samples samples per pixel.
Report convergence_report(const PathScene& scene, Backend backend, const CameraSpec& camera,
                          Extent extent, int max_samples, int reference_samples);

} // namespace rt::ch11
