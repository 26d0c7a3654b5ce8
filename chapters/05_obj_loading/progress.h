// Chapter 05: a progress line for long CPU renders. Brute force over a 100 000-triangle model
// takes the CPU minutes per frame; rather than seconds of silence, a line on stderr every few
// seconds says how far the render has come. The render counts finished rows in a plain
// counter (atomically, from every worker thread); a thread of this class reads it and prints.
#pragma once

#include <chrono>
#include <iosfwd>
#include <string>
#include <thread>

#include "rt/cpu_progress.h"

namespace rt::ch05 {

class Progress {
public:
  // Prints "<what>: 42% of <rows> rows, 12 s" to `out` every `period`, the first time after
  // one period: renders shorter than that print nothing.
  Progress(std::string what, int rows, std::ostream& out,
           std::chrono::milliseconds period = std::chrono::seconds(5));
  // Stops the printing thread; a render that printed and finished also prints "done".
  ~Progress();

  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // The counter the render increments once per finished row.
  unsigned* rows_done() { return &rows_done_; }

private:
  void print_line(bool done);

  std::string what_;
  int rows_;
  std::ostream& out_;
  std::chrono::steady_clock::time_point start_;
  unsigned rows_done_ = 0; // written by the render's threads with atomic increments
  int lines_ = 0;          // written by the printing thread, read after it has stopped
  QuietCpuProgress quiet_; // this line replaces the launch helper's own (rt/cpu_progress.h)
  std::jthread printer_;   // declared last: stopped and joined before the rest goes
};

} // namespace rt::ch05
