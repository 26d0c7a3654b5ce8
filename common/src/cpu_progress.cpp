// Progress of long CPU work (chapter 01): see rt/cpu_progress.h.
#include "rt/cpu_progress.h"

#include <atomic>
#include <cstdio>
#include <iostream>
#include <ostream>
#include <utility>

namespace rt {

namespace {

thread_local std::string current_name = "working on the CPU";
std::atomic<int> quiet_count{0};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void print(std::ostream& out, const std::string& line) {
  std::cout.flush(); // keeps the report's lines and these in order when both go to a terminal
  out << line << std::endl;
}

} // namespace

CpuProgress::CpuProgress(long long total, const char* unit, std::ostream& out,
                         std::chrono::milliseconds period)
    : what_(current_name), out_(out), period_(period), total_(total), unit_(unit),
      start_(std::chrono::steady_clock::now()), next_line_(start_ + period) {}

CpuProgress::~CpuProgress() {
  if (!printed_) return;
  char line[64];
  std::snprintf(line, sizeof line, ": done in %.0f s", seconds_since(start_));
  print(out_, what_ + line);
}

void CpuProgress::update(long long done) {
  const auto now = std::chrono::steady_clock::now();
  if (now < next_line_) return;
  next_line_ = now + period_;
  if (quiet_count.load(std::memory_order_relaxed) > 0) return;
  const double percent = total_ > 0 ? 100.0 * double(done) / double(total_) : 100.0;
  char line[128];
  if (unit_ != nullptr)
    std::snprintf(line, sizeof line, ": %.0f%% (%lld of %lld %s), %.0f s", percent, done,
                  total_, unit_, seconds_since(start_));
  else
    std::snprintf(line, sizeof line, ": %.0f%%, %.0f s", percent, seconds_since(start_));
  print(out_, what_ + line);
  printed_ = true;
}

CpuWorkName::CpuWorkName(std::string name) : previous_(std::exchange(current_name, name)) {}

CpuWorkName::~CpuWorkName() { current_name = std::move(previous_); }

QuietCpuProgress::QuietCpuProgress() { quiet_count.fetch_add(1, std::memory_order_relaxed); }

QuietCpuProgress::~QuietCpuProgress() { quiet_count.fetch_sub(1, std::memory_order_relaxed); }

} // namespace rt
