// Chapter 11: choosing a kernel's features once, at the edge: the specialised kernel for the
// scene's set (chapter 06's with_specialised) or the all-features kernel, whose every feature
// is compiled in and switched by the scene's flags at run time.
#pragma once

#include "feature_sets.h"
#include "path_trace.h"
#include "shaded_render.h"

namespace rt::ch11 {

static_assert(k_all_path_features == ch06::k_all_features,
              "chapter 06's with_specialised() has a case for every set of these features");

// Calls launch(features) with Specialised<set> or AllFeatures{set}.
template <class Launch>
void with_kernel(ch06::KernelKind kernel, unsigned features, Launch&& launch) {
  if (kernel == ch06::KernelKind::all_features) return launch(ch06::AllFeatures{features});
  ch06::with_specialised(features, [&](auto specialised) { launch(specialised); });
}

} // namespace rt::ch11
