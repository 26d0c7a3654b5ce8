// Chapter 05: unpacking gzip data. See gunzip.h.
#include "gunzip.h"

#include <algorithm>
#include <array>

#include <zlib.h>

#include "rt/error.h"

namespace rt::ch05 {

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw InputError(name + ": " + what);
}

// zlib's inflate state, released on every path out.
struct Inflater {
  z_stream stream{};
  bool started = false;
  Inflater() = default;
  Inflater(const Inflater&) = delete;
  Inflater& operator=(const Inflater&) = delete;
  ~Inflater() {
    if (started) inflateEnd(&stream);
  }
};

} // namespace

bool is_gzip(std::string_view bytes) {
  return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
         static_cast<unsigned char>(bytes[1]) == 0x8b;
}

// The output grows 64 KiB at a time and is checked against the cap before each piece is
// kept; nothing is reserved for the size that the data claims (its trailer can lie).
// Several gzip members one after another (`cat a.gz b.gz > ab.gz`) are one valid file.
std::string gunzip(std::string_view packed, const std::string& name_for_errors,
                   long long max_bytes) {
  const std::string& name = name_for_errors;
  Inflater z;
  if (inflateInit2(&z.stream, 16 + MAX_WBITS) != Z_OK) fail(name, "zlib failed to start");
  z.started = true;
  std::string text;
  std::array<unsigned char, 1 << 16> chunk{};
  std::size_t fed = 0; // bytes of `packed` handed to zlib so far
  for (;;) {
    if (z.stream.avail_in == 0 && fed < packed.size()) {
      // zlib counts input in 32-bit unsigned ints: feed it at most 1 GiB at a time.
      const std::size_t piece = std::min<std::size_t>(packed.size() - fed, 1u << 30);
      z.stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(packed.data() + fed));
      z.stream.avail_in = static_cast<uInt>(piece);
      fed += piece;
    }
    z.stream.next_out = chunk.data();
    z.stream.avail_out = static_cast<uInt>(chunk.size());
    const int status = inflate(&z.stream, Z_NO_FLUSH);
    const std::size_t produced = chunk.size() - z.stream.avail_out;
    if (static_cast<long long>(text.size() + produced) > max_bytes) {
      fail(name, "decompresses to more than LoadLimits::max_file_bytes (" +
                     std::to_string(max_bytes) + " bytes)");
    }
    text.append(reinterpret_cast<const char*>(chunk.data()), produced);
    if (status == Z_STREAM_END) {
      const std::string_view rest = packed.substr(fed - z.stream.avail_in);
      if (rest.empty()) return text;
      if (!is_gzip(rest)) fail(name, "unexpected bytes after the end of the gzip data");
      inflateReset(&z.stream); // the next member
      continue;
    }
    // inflate() makes progress on every call or says why not: the loop cannot spin.
    if (status == Z_BUF_ERROR && z.stream.avail_in == 0 && fed == packed.size()) {
      fail(name, "truncated gzip data (the file ends inside the compressed stream)");
    }
    if (status != Z_OK) {
      fail(name, std::string("corrupt gzip data (zlib: ") +
                     (z.stream.msg != nullptr ? z.stream.msg : zError(status)) + ")");
    }
  }
}

} // namespace rt::ch05
