// Chapter 11: what every program that renders with a ProgressiveRenderer does alike (this
// chapter's and the next): the window's frames, and the flags it refuses in one line rather
// than ignore.
#pragma once

#include <optional>
#include <utility>

#include <CLI/CLI.hpp>

#include "path_render.h"
#include "program.h"

namespace rt::ch11 {

// --sampler NAME (settings.sampler) and --samplers (compare_samplers: --convergence measures
// the samplers instead of the strategies).
void add_sampler_options(CLI::App& app, RenderSettings& settings, bool& compare_samplers);

// Throws UsageError for flags the run would not read: with `convergence`, the image's flags
// (--window, --variant, --strategy, --sampler, --output, --seconds, --image-only, --exposure,
// --frames); --reference-spp and --samplers without it; --spp with --seconds; --exposure
// without a tone-mapped picture to scale; an --output "" that leaves the run nothing to write.
void refuse_progressive_flags(const CLI::App& app, const ch03::ProgramOptions& options,
                              bool convergence);

// The view a window showed last: its camera and size.
using ShownView = std::optional<std::pair<CameraSpec, Extent>>;

// One frame of the window: the sums go on while the view stays `shown`, and start again when
// the camera or the size changed; one more sample per pixel, tone-mapped into `pixels`
// (backend memory). `shown` becomes this frame's view.
void add_window_frame(ProgressiveRenderer& renderer, ShownView& shown, const CameraSpec& camera,
                      Extent extent, const RenderSettings& settings, float exposure,
                      Rgba8* pixels);

} // namespace rt::ch11
