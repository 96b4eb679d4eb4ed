#pragma once
// How much memory this process holds, for the soak test's "memory stays
// flat" check. Reading it allocates nothing. Linux (glibc): elsewhere, or
// under a sanitizer that replaces malloc, the figures are 0 (unknown).
#include <cstddef>

namespace stridemap {

struct ProcessMemory {
  /// Bytes handed out by malloc and not yet freed (glibc's main arena:
  /// mallinfo2().uordblks + hblkhd), 0 when unknown.
  std::size_t heap_in_use_bytes = 0;
  /// Resident set size (/proc/self/statm), 0 when unknown.
  std::size_t resident_bytes = 0;
};

ProcessMemory process_memory();

}  // namespace stridemap
