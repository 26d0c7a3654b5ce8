// Chapter 08: the ways a traversal can read its tree, as named variants. Every path reads the
// same numbers and runs the same traversal (chapter 07's trace_bvh); only the load
// instructions and the caches they go through differ, so every path must give chapter 07's
// hits bit for bit.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "rt/backend.h"

namespace rt::ch08 {

// [listing:memory_paths]
enum class MemoryPath {
  global,     // chapter 07 as it is: 64-byte nodes, 36-byte triangles, plain loads
  ldg,        // the same layout, every word through the read-only data cache (__ldg)
  float4,     // 16-byte records: each node is 4 float4, each triangle 3 (id in a spare lane)
  float4_ldg, // the same records through the read-only data cache
  texture,    // the same records as texture objects over linear memory (tex1Dfetch)
};
// [/listing:memory_paths]

inline constexpr MemoryPath k_all_paths[] = {MemoryPath::global, MemoryPath::ldg,
                                             MemoryPath::float4, MemoryPath::float4_ldg,
                                             MemoryPath::texture};

const char* to_string(MemoryPath path);
// The name's path; throws UsageError naming the accepted names otherwise.
MemoryPath parse_memory_path(std::string_view name);
// "global,float4" or "all": the paths named, in the order of k_all_paths, each once.
std::vector<MemoryPath> parse_memory_paths(std::string_view list);
// One line for the report: the layout and the load instruction.
const char* describe(MemoryPath path);

// A processor has only the paths it has the hardware for: the read-only data cache and the
// texture unit are the GPU's. The CPU runs global and float4.
bool runs_on(MemoryPath path, Backend backend);
// Throws UsageError, naming the path and the backend, where runs_on is false.
void check_runs_on(MemoryPath path, Backend backend);

} // namespace rt::ch08
