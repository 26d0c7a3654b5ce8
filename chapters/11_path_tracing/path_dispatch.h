// Chapter 11: choosing a kernel's features once, at the edge: the specialised kernel for the
// scene's set (chapter 06's with_specialised) or the all-features kernel, whose every feature
// is compiled in and switched by the scene's flags at run time.
#pragma once

#include "feature_sets.h"
#include "path_trace.h"
#include "rt/launch.h"
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

// Runs fn(i) for i in [0, count) on the backend: a work list as the launch helper's rows of
// 1024 items.
template <class ItemFn> struct ItemsAsPixels {
  ItemFn fn;
  long long count;
  RT_HD void operator()(int x, int y) const {
    const long long i = static_cast<long long>(y) * k_row + x;
    if (i < count) fn(static_cast<int>(i));
  }
  static constexpr int k_row = 1024;
};

template <class ItemFn> void for_each_item(Backend backend, long long count, ItemFn fn) {
  if (count <= 0) return;
  constexpr int row = ItemsAsPixels<ItemFn>::k_row;
  const Extent rows{static_cast<int>(count < row ? count : row),
                    static_cast<int>((count + row - 1) / row)};
  for_each_pixel(backend, rows, ItemsAsPixels<ItemFn>{fn, count}, BlockShape{128, 1});
}

} // namespace rt::ch11
