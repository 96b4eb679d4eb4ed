#pragma once
// Test programs that count allocations replace the global operator new.
// ThreadSanitizer's runtime defines operator new itself (a second
// definition does not link), so under `make test-tsan` the replacement is
// left out and those tests skip; they run in the plain and ASan builds.
#if defined(__SANITIZE_THREAD__)
#define STRIDEMAP_ALLOCATION_COUNTING 0
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define STRIDEMAP_ALLOCATION_COUNTING 0
#endif
#endif
#ifndef STRIDEMAP_ALLOCATION_COUNTING
#define STRIDEMAP_ALLOCATION_COUNTING 1
#endif

#define STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS()                                           \
  if (!STRIDEMAP_ALLOCATION_COUNTING)                                                          \
  GTEST_SKIP() << "allocation counting is off under ThreadSanitizer (its runtime owns operator new)"
