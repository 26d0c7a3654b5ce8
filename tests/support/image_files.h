// Tests that read what a program wrote: PNG, PFM and EXR files back into the course's image
// types, row 0 at the top. A file that cannot be read fails the test that asked for it.
#pragma once

#include <filesystem>

#include "rt/image.h"

namespace rt::testing {

Image read_png(const std::filesystem::path& path);
LinearImage read_pfm(const std::filesystem::path& path); // the file holds the bottom row first
LinearImage read_exr(const std::filesystem::path& path); // through tinyexr's LoadEXR

} // namespace rt::testing
