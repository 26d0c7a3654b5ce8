// Chapter 01: the report's rows. Each kernel's image against the CPU reference, and what the
// flat offset check wrote wrong: pixels never written, written twice, writes past the end.
#pragma once

#include <string>
#include <vector>

#include "first_kernel.h"
#include "rt/image.h"
#include "rt/report.h"
#include "rt/timer.h"

namespace rt::ch01 {

// The flat offset check's row: its time, and the pixels it missed or wrote twice.
ReportRow audit_row(std::string variant, Backend backend, const Timing& timing, Extent extent,
                    BlockShape block);

// The GPU's rows: the hand-written kernel and the launch helper against the CPU reference,
// then the flat offset check. Returns the launch helper's image.
Image report_gpu_kernels(Extent extent, BlockShape block, int frames, const Image& reference,
                         Report& report);

// Where the flat offset check went wrong: wrong pixels in white, the rest dimmed.
Image flat_offset_damage(const Image& reference, const std::vector<Rgba8>& flat_image);

} // namespace rt::ch01
