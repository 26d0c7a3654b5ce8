// Progress of long CPU work (chapter 01). The CPU backend is hundreds of times slower than a
// GPU, and a render, a reference or a build that takes minutes must say how far it has come
// rather than sit silent: once work has run for five seconds, and every five seconds after, a
// line goes to stderr, "<what>: 37% (312 of 720 rows), 15 s".
#pragma once

#include <chrono>
#include <iostream>
#include <string>

namespace rt {

class CpuProgress {
public:
  // Work of `total` items named by `unit` ("rows", "rays"; null: the line shows only the
  // percentage), called what the innermost live CpuWorkName of this thread says ("working on
  // the CPU" without one). Lines go to `out` every `period`, the first after one period.
  CpuProgress(long long total, const char* unit, std::ostream& out = std::cerr,
              std::chrono::milliseconds period = std::chrono::seconds(5));
  // Prints "<what>: done in 15 s" if it printed anything before.
  ~CpuProgress();
  CpuProgress(const CpuProgress&) = delete;
  CpuProgress& operator=(const CpuProgress&) = delete;

  // `done` of the total items are finished; prints when a period has passed since the last
  // line. Call it from the thread that made this object only.
  void update(long long done);

private:
  std::string what_;
  std::ostream& out_;
  std::chrono::milliseconds period_;
  long long total_;
  const char* unit_;
  std::chrono::steady_clock::time_point start_, next_line_;
  bool printed_ = false;
};

// Names the CPU work that this thread starts while it lives ("float64 reference"), for the
// progress lines; the previous name comes back when it goes.
class CpuWorkName {
public:
  explicit CpuWorkName(std::string name);
  ~CpuWorkName();
  CpuWorkName(const CpuWorkName&) = delete;
  CpuWorkName& operator=(const CpuWorkName&) = delete;

private:
  std::string previous_;
};

// While one lives, CpuProgress prints nothing: for a caller that shows its own progress line
// (chapter 05's Progress), so that the reader does not get two.
class QuietCpuProgress {
public:
  QuietCpuProgress();
  ~QuietCpuProgress();
  QuietCpuProgress(const QuietCpuProgress&) = delete;
  QuietCpuProgress& operator=(const QuietCpuProgress&) = delete;
};

} // namespace rt
