// Chapter 11: the flags a progressive renderer's program refuses in one line rather than
// ignore, shared by every program that renders with a ProgressiveRenderer (this chapter's and
// the next).
#pragma once

#include <CLI/CLI.hpp>

#include "program.h"

namespace rt::ch11 {

// Throws UsageError for flags the run would not read: with `convergence`, the image's flags
// (--window, --variant, --strategy, --output, --seconds, --image-only, --exposure, --frames);
// --reference-spp without it; --spp with --seconds; --exposure without a tone-mapped picture
// to scale; an --output "" that leaves the run nothing to write.
void refuse_progressive_flags(const CLI::App& app, const ch03::ProgramOptions& options,
                              bool convergence);

} // namespace rt::ch11
