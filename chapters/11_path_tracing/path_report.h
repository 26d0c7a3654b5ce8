// Chapter 11: the program's two reports. The kernels' rows (time per sample and whether each
// gives the same sums as the specialised megakernel), and the error against run time of every
// strategy and variant against a float64 reference.
#pragma once

#include <chrono>
#include <iostream>

#include "convergence.h"
#include "moving_path.h"
#include "path_render.h"
#include "rt/backend.h"
#include "rt/report.h"

namespace rt::ch11 {

// The specialised megakernel, the all-features megakernel and the specialised wavefront, each
// with the settings' strategy and sampler, timed over `frames` passes of one sample per pixel
// (0: the protocol's count) from a fresh start, so that each ends with the same samples: their
// sums are compared bit for bit.
// On the GPU it adds add_tail_row's row.
void add_kernel_rows(ProgressiveRenderer& renderer, const RenderSettings& settings,
                     const CameraSpec& camera, Extent extent, int frames, Report& report);

// The wavefront timed in calls of k_samples_a_call samples, where each sample's stragglers
// run beside the next sample (wavefront_stages.cuh): the milliseconds per sample, and its sums
// against the megakernel's after as many samples. `first_ms` is the first row's time.
inline constexpr int k_samples_a_call = 8;
void add_tail_row(ProgressiveRenderer& renderer, const RenderSettings& wavefront,
                  const CameraSpec& camera, Extent extent, int frames, double rays_per_path,
                  double first_ms, Report& report);

// --moving: `frames` frames of the renderer's moving scene (60 for 0), each moved on the
// backend (its vertices, its tree built and collapsed) and given one sample per pixel by
// `settings`. The row gives a frame's mean time and its four parts, as chapter 10's report
// does: animate, tree, collapse and render (GPU: CUDA events between them; CPU: wall time),
// and the frames per second by the wall clock. A progress line every `period` on `progress`
// counts the frames ("moving scene: 37% (37000 of 100000 frames), 15 s").
void add_moving_rows(MovingPathRenderer& renderer, const RenderSettings& settings,
                     const CameraSpec& camera, Extent extent, int frames, Report& report,
                     std::ostream& progress = std::cerr,
                     std::chrono::milliseconds period = std::chrono::seconds(5));

// The most samples per pixel an image takes (--spp, --reference-spp, --seconds): a pixel's
// float sum counts its samples exactly up to 2^24, and its radiance keeps 1/16 of float's
// precision at this count.
inline constexpr int k_max_samples_per_pixel = 1 << 20;

// The image's samples are added in passes of about this many paths, a fraction of a second
// on the CPU, so that long work (a tiny image of a million samples per pixel, a long
// --seconds) can say how far it has come between passes.
inline constexpr long long k_paths_per_pass = 1 << 16;
// The GPU's passes are larger, 8 samples of 1920x1080 (a tenth of a second for chapter 12's
// room on an H200): within a pass, the wavefront finishes each sample's stragglers beside
// the next sample (wavefront_stages.cuh).
inline constexpr long long k_gpu_paths_per_pass = 1 << 24;

struct SamplesTaken {
  int samples = 0;      // per pixel
  double seconds = 0.0; // wall time, the backend's work waited for
};

// The image's samples: `spp` per pixel, or, when `seconds` is above 0, passes until that time
// is up (at most k_max_samples_per_pixel). The sums are the same as from one add_samples call
// of as many samples. A progress line every `period` on `progress` counts the samples, or
// the seconds ("rendering the image: 37% (388000 of 1048576 samples), 15 s").
SamplesTaken add_image_samples(ProgressiveRenderer& renderer, const RenderSettings& settings,
                               int spp, double seconds, std::ostream& progress = std::cerr,
                               std::chrono::milliseconds period = std::chrono::seconds(5));

// The frames the moving scene is run for: `frames`, or 60 for 0.
inline int moving_frame_count(int frames) { return frames > 0 ? frames : 60; }

// --convergence: a reference of `reference_samples`, then the persistent threads with each
// strategy, and the megakernel and the wavefront with MIS, at 1, 2, 4, ... max_samples samples
// per pixel. `title` heads the report; `scene` describes what the renderer holds.
Report convergence_report(ProgressiveRenderer& renderer, const std::string& title,
                          const std::string& scene, const CameraSpec& camera, Extent extent,
                          int max_samples, int reference_samples);

// --convergence --samplers: the same reference, then the persistent threads with MIS and each
// sampler (samplers.h), each point a fresh image of 1, 2, 4, ... max_samples samples
// (measure_sampler_convergence). The context gives each sampler's fitted slope and its MSE at
// max_samples against the independent sampler's.
Report sampler_convergence_report(ProgressiveRenderer& renderer, const std::string& title,
                                  const std::string& scene, const CameraSpec& camera,
                                  Extent extent, int max_samples, int reference_samples);

} // namespace rt::ch11
