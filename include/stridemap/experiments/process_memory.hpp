#pragma once
// How much memory this process holds, for the soak test's "memory stays
// flat" check. Reading it holds on to nothing it allocates (it fills the
// calling thread's cache of freed blocks first, so that two readings of
// the same holdings agree). Linux (glibc): elsewhere, or under a sanitizer
// that replaces malloc, the figures are 0 (unknown).
#include <cstddef>

namespace stridemap {

struct ProcessMemory {
  /// Bytes handed out by malloc and not yet freed, the calling thread's
  /// full cache of freed blocks included (mallinfo2().uordblks + hblkhd),
  /// 0 when unknown.
  std::size_t heap_in_use_bytes = 0;
  /// Resident set size (/proc/self/statm), 0 when unknown.
  std::size_t resident_bytes = 0;
};

ProcessMemory process_memory();

}  // namespace stridemap
