// The end of a chapter program's run (chapter 01): the --output image with its "wrote" line,
// the report on the terminal and, with --json, in a file. Every chapter's program finishes
// this way, with or without a window.
#pragma once

#include <string>

#include "rt/backend.h"
#include "rt/cli.h"
#include "rt/image.h"
#include "rt/launch.h"
#include "rt/report.h"

namespace rt {

// A report whose context opens with the device the run uses.
Report start_report(std::string title, std::string unit, std::string reference,
                    Backend backend);

// "1280x720".
std::string to_string(Extent extent);

// Writes the image and says so on stdout: "wrote PATH", or "wrote PATH (note)".
void write_output_image(const std::string& path, const Image& image,
                        const std::string& note = "");

// Prints the report and writes it to --json when asked.
void finish_report(const Report& report, const CommonOptions& options);

} // namespace rt
