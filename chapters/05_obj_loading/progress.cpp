// Chapter 05: a progress line for long CPU renders. See progress.h.
#include "progress.h"

#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <ostream>
#include <utility>

namespace rt::ch05 {

Progress::Progress(std::string what, int rows, std::ostream& out,
                   std::chrono::milliseconds period)
    : what_(std::move(what)), rows_(rows), out_(out), start_(std::chrono::steady_clock::now()) {
  printer_ = std::jthread([this, period](std::stop_token stop) {
    std::mutex mutex;
    std::condition_variable_any wake; // woken early only by the stop request
    std::unique_lock lock(mutex);
    for (auto next = start_ + period;; next += period) {
      wake.wait_until(lock, stop, next, [] { return false; });
      if (stop.stop_requested()) return;
      print_line(false);
    }
  });
}

Progress::~Progress() {
  printer_.request_stop();
  printer_.join();
  if (lines_ > 0 && __atomic_load_n(&rows_done_, __ATOMIC_RELAXED) == unsigned(rows_))
    print_line(true);
}

void Progress::print_line(bool done) {
  const unsigned finished = __atomic_load_n(&rows_done_, __ATOMIC_RELAXED);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  char line[64];
  if (done)
    std::snprintf(line, sizeof line, ": done in %.0f s", seconds);
  else
    std::snprintf(line, sizeof line, ": %.0f%% of %d rows, %.0f s",
                  rows_ > 0 ? 100.0 * finished / rows_ : 100.0, rows_, seconds);
  out_ << what_ << line << std::endl; // flushed: the reader is waiting for it
  ++lines_;
}

} // namespace rt::ch05
