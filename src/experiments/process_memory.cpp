#include "stridemap/experiments/process_memory.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstdlib>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace stridemap {
namespace {

// Second field of /proc/self/statm (resident pages), read with plain system
// calls into a stack buffer so that measuring does not allocate.
std::size_t resident_bytes() {
  const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  char text[128];
  const ssize_t got = ::read(fd, text, sizeof text - 1);
  ::close(fd);
  if (got <= 0) return 0;
  text[got] = '\0';
  char* end = nullptr;
  std::strtoull(text, &end, 10);  // total program size
  const unsigned long long pages = std::strtoull(end, &end, 10);
  const long page = ::sysconf(_SC_PAGESIZE);
  return page > 0 ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(page) : 0;
}

#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
// glibc keeps blocks a thread freed, up to a count of each size to 1,032
// bytes (7 by default, the tunable glibc.malloc.tcache_count), for the
// thread's next requests, and mallinfo2() counts them in use. What that
// cache holds depends on the last few hundred frees: two readings of a
// program holding the same memory differed by 2 kB over a soak with the
// global map's tile writes. Taking and freeing more blocks of each size
// than the cache keeps leaves it full, whatever it held before.
void fill_thread_cache() {
  constexpr std::size_t kSmallestRequest = 24;  // each request 16 bytes apart is another size class
  constexpr std::size_t kLargestCachedRequest = 1032;
  constexpr std::size_t kBlocksPerSize = 64;
  // Called through a volatile pointer: a malloc and free the compiler sees
  // as a pair with nothing between may be left out.
  static void* (*volatile const take)(std::size_t) = std::malloc;
  static void (*volatile const give_back)(void*) = std::free;
  void* blocks[kBlocksPerSize];
  for (std::size_t size = kSmallestRequest; size <= kLargestCachedRequest; size += 16) {
    for (void*& block : blocks) block = take(size);
    for (void* block : blocks) give_back(block);
  }
}
#endif

}  // namespace

ProcessMemory process_memory() {
  ProcessMemory memory;
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  fill_thread_cache();
  const struct mallinfo2 info = ::mallinfo2();
  memory.heap_in_use_bytes = info.uordblks + info.hblkhd;
#endif
  memory.resident_bytes = resident_bytes();
  return memory;
}

}  // namespace stridemap
