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

}  // namespace

ProcessMemory process_memory() {
  ProcessMemory memory;
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 info = ::mallinfo2();
  memory.heap_in_use_bytes = info.uordblks + info.hblkhd;
#endif
  memory.resident_bytes = resident_bytes();
  return memory;
}

}  // namespace stridemap
