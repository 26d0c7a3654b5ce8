// Chapter 05: the libFuzzer target for the OBJ loader (built and run by tools/fuzz.sh).
// libFuzzer calls it with millions of generated inputs, mutating the ones that reach new code.
// An input may fail to load, with rt::InputError, but never crash, leak, hang, touch memory it
// does not own (AddressSanitizer), do undefined arithmetic (UndefinedBehaviorSanitizer), throw
// anything else, or load into a mesh that breaks the invariants of mesh_invariants.h.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "mesh_invariants.h"
#include "obj_loader.h"
#include "rt/error.h"

namespace {

[[noreturn]] void bug(const std::string& what) {
  std::fprintf(stderr, "fuzz_obj: %s\n", what.c_str());
  std::abort(); // libFuzzer saves the input that got here as a crash
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // Small limits keep each run fast; the limits themselves are tested in test_ch05.
  rt::ch05::LoadLimits limits;
  limits.max_triangles = 1 << 20;
  limits.max_vertices = 1 << 20;
  limits.max_file_bytes = 8 << 20;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const rt::ch05::ObjMesh mesh = rt::ch05::parse_obj(bytes, "fuzz.obj", limits);
    const std::string violation = rt::testing::mesh_invariant_violation(mesh);
    if (!violation.empty()) bug("mesh loaded with an inconsistent " + violation);
  } catch (const rt::InputError& error) {
    const std::string message = error.what();
    if (message.rfind("fuzz.obj:", 0) != 0) bug("error without the file name: " + message);
    if (message.find('\n') != std::string::npos) bug("error of several lines: " + message);
    if (message.find("tinyobjloader disagrees") != std::string::npos) bug(message);
  }
  return 0;
}
