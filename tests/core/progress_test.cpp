#include "stridemap/core/progress.hpp"

#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace stridemap {
namespace {

TEST(ProgressOfPart, RunsOfOneLoopFillOneBarInOrder) {
  std::vector<std::pair<std::size_t, std::size_t>> seen;
  const ProgressCallback whole = [&](std::size_t done, std::size_t total) { seen.emplace_back(done, total); };
  for (std::size_t part = 0; part < 3; ++part) {
    const ProgressCallback run = progress_of_part(whole, part, 3);
    run(0, 10);
    run(10, 10);
  }
  const std::vector<std::pair<std::size_t, std::size_t>> expected{{0, 30}, {10, 30}, {10, 30},
                                                                  {20, 30}, {20, 30}, {30, 30}};
  EXPECT_EQ(seen, expected);
}

TEST(ProgressOfPart, AnUnknownTotalCountsWholeRunsAndNoListenerGivesNoCallback) {
  std::pair<std::size_t, std::size_t> last{};
  const ProgressCallback whole = [&](std::size_t done, std::size_t total) { last = {done, total}; };
  progress_of_part(whole, 2, 5)(7, 0);
  EXPECT_EQ(last, (std::pair<std::size_t, std::size_t>{2, 5}));
  EXPECT_FALSE(progress_of_part(ProgressCallback{}, 0, 2));
}

}  // namespace
}  // namespace stridemap
