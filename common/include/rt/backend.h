// Backend selection (chapter 01): every chapter runs the same per-pixel function either as a
// CUDA kernel or on CPU threads. `auto` picks the GPU when one is usable.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace rt {

enum class Backend { automatic, gpu, cpu };

const char* to_string(Backend backend);
// Parses "auto", "gpu" or "cpu"; anything else is a UsageError.
Backend parse_backend(std::string_view text);

struct GpuInfo {
  bool usable = false;        // a CUDA device exists and this build has code for it
  std::string name;           // e.g. "NVIDIA H200"
  int compute_capability = 0; // e.g. 90
  int multiprocessors = 0;
  std::string why_unusable; // one line, when !usable
};

// Probes device 0 once per process (later calls return the cached answer).
const GpuInfo& gpu_info();

// Turns a requested backend into gpu or cpu. `automatic` falls back to the CPU and writes one
// notice line to `notice`; `gpu` without a usable device throws NoGpuError.
Backend resolve_backend(Backend requested, std::ostream& notice);

// The backends a chapter's report measures on: the resolved one, and after the GPU also the
// CPU unless `skip_cpu` (--skip-cpu).
std::vector<Backend> report_backends(Backend resolved, bool skip_cpu);

// Threads the CPU backend uses: the hardware's count, or RT_CPU_THREADS when set.
int cpu_thread_count();

// A short description of where a backend runs: the GPU's name or "N CPU threads".
std::string describe_backend(Backend resolved);

} // namespace rt
