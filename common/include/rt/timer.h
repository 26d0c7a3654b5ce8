// Timing as the benchmark protocol prescribes it (chapter 01; the book's appendix A): warm-up
// runs first, then the median of many timed runs. GPU runs are timed with CUDA events around
// the launch only; CPU runs with a steady clock.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

#include "rt/backend.h"
#include "rt/device_buffer.h"

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

} // namespace rt
