// An atomic increment that works on both backends (chapter 01): tests use it to count how
// often each pixel is written.
#pragma once

#include "rt/hd.h"

namespace rt {

RT_HD inline unsigned atomic_increment(unsigned* counter) {
#if RT_ON_DEVICE
  return atomicAdd(counter, 1u);
#else
  return __atomic_fetch_add(counter, 1u, __ATOMIC_RELAXED);
#endif
}

} // namespace rt
