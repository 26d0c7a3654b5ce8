// Chapter 05: unpacking gzip data (.obj.gz) with zlib, in chunks and with a cap, because a
// few kilobytes of gzip can unpack to terabytes.
#pragma once

#include <string>
#include <string_view>

namespace rt::ch05 {

// True when the bytes start with gzip's magic number (1f 8b). No text file starts that way,
// so the first two bytes decide, whatever the file is called.
bool is_gzip(std::string_view bytes);

// The data that `packed` (one or more gzip members) holds. Throws rt::InputError, naming
// `name_for_errors`, for truncated or corrupt data, for bytes after the end, and as soon as
// the output passes max_bytes.
std::string gunzip(std::string_view packed, const std::string& name_for_errors,
                   long long max_bytes);

} // namespace rt::ch05
