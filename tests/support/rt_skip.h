// RT_SKIP(reason): the test case stops here and is reported as skipped, never as passed: a test
// of code this build did not compile, say. Catch2 v3 has SKIP; v2 has none, so there it prints
// "SKIPPED: reason" and returns, and CTest, which looks for that line in every test's output
// (SKIP_REGULAR_EXPRESSION, cmake/RtChapter.cmake), counts the test as skipped, whatever else
// it printed: so RT_SKIP comes before a test's first assertion, never after one.
#pragma once

#include "rt_catch.h"

#if RT_CATCH_V3
#define RT_SKIP(reason) SKIP(reason)
#else
#define RT_SKIP(reason)                                                                        \
  do {                                                                                         \
    WARN("SKIPPED: " << reason);                                                               \
    return;                                                                                    \
  } while (false)
#endif
