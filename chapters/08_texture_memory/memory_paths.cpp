// Chapter 08: the memory paths' names. See memory_paths.h.
#include "memory_paths.h"

#include <algorithm>

#include "rt/error.h"

namespace rt::ch08 {

const char* to_string(MemoryPath path) {
  switch (path) {
  case MemoryPath::global:
    return "global";
  case MemoryPath::ldg:
    return "ldg";
  case MemoryPath::float4:
    return "float4";
  case MemoryPath::float4_ldg:
    return "float4_ldg";
  case MemoryPath::texture:
    return "texture";
  }
  return "?";
}

MemoryPath parse_memory_path(std::string_view name) {
  for (const MemoryPath path : k_all_paths)
    if (name == to_string(path)) return path;
  throw UsageError("unknown memory path '" + std::string(name) +
                   "' (global, ldg, float4, float4_ldg, texture or all)");
}

std::vector<MemoryPath> parse_memory_paths(std::string_view list) {
  if (list == "all") return {std::begin(k_all_paths), std::end(k_all_paths)};
  std::vector<bool> wanted(std::size(k_all_paths), false);
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = list.find(',', start);
    const std::string_view name = list.substr(start, comma - start);
    wanted[static_cast<std::size_t>(parse_memory_path(name))] = true;
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  std::vector<MemoryPath> paths;
  for (const MemoryPath path : k_all_paths)
    if (wanted[static_cast<std::size_t>(path)]) paths.push_back(path);
  return paths;
}

const char* describe(MemoryPath path) {
  switch (path) {
  case MemoryPath::global:
    return "64 B nodes, 36 B triangles + ids; plain loads";
  case MemoryPath::ldg:
    return "same layout; every word with __ldg (read-only cache)";
  case MemoryPath::float4:
    return "16 B records: 4 per node, 3 per triangle; float4 loads";
  case MemoryPath::float4_ldg:
    return "16 B records; float4 __ldg loads";
  case MemoryPath::texture:
    return "16 B records; texture objects, tex1Dfetch<float4>";
  }
  return "?";
}

bool runs_on(MemoryPath path, Backend backend) {
  if (backend == Backend::gpu) return true;
  return path == MemoryPath::global || path == MemoryPath::float4;
}

void check_runs_on(MemoryPath path, Backend backend) {
  if (runs_on(path, backend)) return;
  throw UsageError(std::string("memory path '") + to_string(path) + "' needs the GPU (" +
                   (path == MemoryPath::texture ? "texture unit" : "read-only data cache") +
                   "); on the " + to_string(backend) + " use global or float4");
}

} // namespace rt::ch08
