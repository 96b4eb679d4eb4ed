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

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <thread>

namespace stridemap::test {

/// The counter behind a test program's one replacement of operator new.
/// Exactly one file of the program expands STRIDEMAP_REPLACE_OPERATOR_NEW();
/// every test of it that counts uses allocation_counter().
struct AllocationCounter {
  std::atomic<bool> counting{false};
  std::atomic<std::size_t> allocations{0};
  /// When set, only this thread's allocations count (a test whose helper
  /// threads, such as a device emulator, are not what it measures).
  std::atomic<std::thread::id> only_thread{};
  bool counts_here() const {
    if (!counting.load(std::memory_order_relaxed)) return false;
    const std::thread::id only = only_thread.load(std::memory_order_relaxed);
    return only == std::thread::id{} || only == std::this_thread::get_id();
  }
};
AllocationCounter& allocation_counter();

/// Counts the allocations made while it lives, from zero.
class Counting {
 public:
  Counting() {
    allocation_counter().allocations = 0;
    allocation_counter().counting = true;
  }
  ~Counting() { allocation_counter().counting = false; }
  Counting(const Counting&) = delete;
  Counting& operator=(const Counting&) = delete;
  std::size_t allocations() const { return allocation_counter().allocations.load(); }
};

}  // namespace stridemap::test

#define STRIDEMAP_DEFINE_ALLOCATION_COUNTER()                       \
  stridemap::test::AllocationCounter& stridemap::test::allocation_counter() { \
    static AllocationCounter counter;                                \
    return counter;                                                  \
  }

#if STRIDEMAP_ALLOCATION_COUNTING
#define STRIDEMAP_REPLACE_OPERATOR_NEW()                                                            \
  STRIDEMAP_DEFINE_ALLOCATION_COUNTER()                                                             \
  void* operator new(std::size_t size) {                                                            \
    stridemap::test::AllocationCounter& c = stridemap::test::allocation_counter();                  \
    if (c.counts_here()) c.allocations.fetch_add(1, std::memory_order_relaxed);                      \
    if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;                            \
    throw std::bad_alloc();                                                                         \
  }                                                                                                 \
  void operator delete(void* memory) noexcept { std::free(memory); }                               \
  void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }                  \
  /* Every other unaligned form too: under AddressSanitizer a form left to  */                     \
  /* its runtime (the nothrow new std::stable_sort's buffer uses) would be */                      \
  /* freed by the delete above, an alloc-dealloc mismatch.                 */                      \
  void* operator new(std::size_t size, const std::nothrow_t&) noexcept {                          \
    stridemap::test::AllocationCounter& c = stridemap::test::allocation_counter();                  \
    if (c.counts_here()) c.allocations.fetch_add(1, std::memory_order_relaxed);                      \
    return std::malloc(size == 0 ? 1 : size);                                                       \
  }                                                                                                 \
  void operator delete(void* memory, const std::nothrow_t&) noexcept { std::free(memory); }        \
  void* operator new[](std::size_t size) { return ::operator new(size); }                          \
  void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {                     \
    return ::operator new(size, tag);                                                               \
  }                                                                                                 \
  void operator delete[](void* memory) noexcept { std::free(memory); }                             \
  void operator delete[](void* memory, std::size_t) noexcept { std::free(memory); }                \
  void operator delete[](void* memory, const std::nothrow_t&) noexcept { std::free(memory); }
#else
#define STRIDEMAP_REPLACE_OPERATOR_NEW() STRIDEMAP_DEFINE_ALLOCATION_COUNTER()
#endif
