// Timing as the benchmark protocol prescribes it (chapter 01; the book's appendix A): warm-up
// runs first, then the median of many timed runs. GPU runs are timed with CUDA events around
// the launch only; CPU runs with a steady clock.
#pragma once

#include <algorithm>
#include <chrono>
#include <optional>
#include <vector>

#include "rt/backend.h"
#include "rt/device_buffer.h"
#include "rt/error.h"

namespace rt {

struct Timing {
  double median_ms = 0.0; // the figure every report quotes
  double min_ms = 0.0;
  double max_ms = 0.0;
  int runs = 0;
};

struct TimingPlan {
  int warmups = 0;
  int runs = 0;
};

// The protocol's minimums: GPU 5 warm-ups + 50 runs, CPU 1 warm-up + 5 runs. A positive
// `frames` (the --frames option) replaces the number of timed runs on both.
TimingPlan timing_plan(Backend resolved, int frames = 0);

// Median, minimum and maximum of a set of samples in milliseconds.
Timing summarize(std::vector<double> samples_ms);

template <class Run> Timing time_cpu(Run&& run, TimingPlan plan) {
  for (int i = 0; i < plan.warmups; ++i) run();
  std::vector<double> samples;
  for (int i = 0; i < plan.runs; ++i) {
    const auto start = std::chrono::steady_clock::now();
    run();
    const auto stop = std::chrono::steady_clock::now();
    samples.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
  }
  return summarize(std::move(samples));
}

// `launch` enqueues GPU work on the default stream; only that work is timed.
// [listing:time_gpu]
template <class Launch> Timing time_gpu(Launch&& launch, TimingPlan plan) {
  for (int i = 0; i < plan.warmups; ++i) launch();
  CudaEvent start, stop;
  std::vector<double> samples;
  for (int i = 0; i < plan.runs; ++i) {
    start.record();
    launch();
    stop.record();
    stop.synchronize();
    samples.push_back(stop.milliseconds_since(start));
  }
  return summarize(std::move(samples));
}
// [/listing:time_gpu]

// Times `run` on the given resolved backend with the protocol's plan.
template <class Run> Timing time_on(Backend resolved, Run&& run, int frames = 0) {
  const TimingPlan plan = timing_plan(resolved, frames);
  return resolved == Backend::gpu ? time_gpu(run, plan) : time_cpu(run, plan);
}

// Marks in a run of work on either resolved backend, and the milliseconds between two of them:
// CUDA events on the GPU, which time the work enqueued on the default stream between the marks,
// and the steady clock on the CPU, whose work is done when the call that marks returns.
class BackendClock {
public:
  BackendClock(Backend resolved, int marks) : backend_(resolved), wall_(marks) {
    if (resolved != Backend::gpu && resolved != Backend::cpu)
      throw Error("BackendClock: resolve the backend first");
    if (backend_ == Backend::gpu) {
      events_ = std::vector<std::optional<CudaEvent>>(marks);
      for (std::optional<CudaEvent>& event : events_) event.emplace();
    }
  }
  void mark(int i) {
    if (backend_ == Backend::gpu)
      events_.at(i)->record();
    else
      wall_.at(i) = std::chrono::steady_clock::now();
  }
  // From mark a to mark b; on the GPU it first waits until the work before mark b is done.
  double milliseconds_between(int a, int b) {
    if (backend_ == Backend::gpu) {
      events_.at(b)->synchronize();
      return events_.at(b)->milliseconds_since(*events_.at(a));
    }
    return std::chrono::duration<double, std::milli>(wall_.at(b) - wall_.at(a)).count();
  }

private:
  Backend backend_;
  std::vector<std::optional<CudaEvent>> events_;            // the GPU's only
  std::vector<std::chrono::steady_clock::time_point> wall_; // the CPU's only
};

// A BackendClock of two marks, the first made with it: the time of all the work since.
class BackendStopwatch {
public:
  explicit BackendStopwatch(Backend resolved) : clock_(resolved, 2) { clock_.mark(0); }
  double milliseconds() {
    clock_.mark(1);
    return clock_.milliseconds_between(0, 1);
  }

private:
  BackendClock clock_;
};

} // namespace rt
