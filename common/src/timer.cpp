// Timing (chapter 01): see rt/timer.h.
#include "rt/timer.h"

#include <stdexcept>

namespace rt {

TimingPlan timing_plan(Backend resolved, int frames) {
  TimingPlan plan = resolved == Backend::gpu ? TimingPlan{5, 50} : TimingPlan{1, 5};
  if (frames > 0) plan.runs = frames;
  return plan;
}

Timing summarize(std::vector<double> samples_ms) {
  if (samples_ms.empty()) throw std::invalid_argument("summarize: no samples");
  std::sort(samples_ms.begin(), samples_ms.end());
  const std::size_t n = samples_ms.size();
  const double median =
      n % 2 == 1 ? samples_ms[n / 2] : 0.5 * (samples_ms[n / 2 - 1] + samples_ms[n / 2]);
  return {median, samples_ms.front(), samples_ms.back(), static_cast<int>(n)};
}

} // namespace rt
