// The experiments test program's one replacement of operator new, shared by
// the tests that count allocations (the long walk, the soak).
#include <memory>

#include <gtest/gtest.h>

#include "allocation_counting.hpp"

STRIDEMAP_REPLACE_OPERATOR_NEW()

namespace stridemap::test {
namespace {

TEST(AllocationCounter, CountsOnlyWhileOn) {
  STRIDEMAP_SKIP_UNLESS_COUNTING_ALLOCATIONS();
  AllocationCounter& c = allocation_counter();
  c.allocations = 0;
  c.counting = true;
  auto counted = std::make_unique<int>(1);
  c.counting = false;
  auto uncounted = std::make_unique<int>(2);
  EXPECT_EQ(c.allocations.load(), 1u);
}

}  // namespace
}  // namespace stridemap::test
