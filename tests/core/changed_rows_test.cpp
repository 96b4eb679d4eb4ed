// ChangedRows (core/changed_rows.hpp): per-row spans of changed cells kept
// in a ring of one window's rows.
#include <gtest/gtest.h>

#include "stridemap/core/changed_rows.hpp"

namespace stridemap {
namespace {

TEST(ChangedRows, KeepsEachRowsSmallestAndLargestColumn) {
  ChangedRows rows(10);
  EXPECT_TRUE(rows.empty());
  rows.add(CellIndex{-3, 5});
  rows.add(CellIndex{-3, -2});
  rows.add_span(4, 7, 9);
  rows.add_span(4, 8, 1);  // lo > hi: nothing
  std::int64_t lo = 0, hi = 0;
  ASSERT_TRUE(rows.span(-3, lo, hi));
  EXPECT_EQ(lo, -2);
  EXPECT_EQ(hi, 5);
  ASSERT_TRUE(rows.span(4, lo, hi));
  EXPECT_EQ(lo, 7);
  EXPECT_EQ(hi, 9);
  EXPECT_FALSE(rows.span(0, lo, hi));
  EXPECT_FALSE(rows.span(7, lo, hi));  // shares -3's place in the ring
  EXPECT_EQ(rows.bounds().min, (CellIndex{-3, -2}));
  EXPECT_EQ(rows.bounds().max, (CellIndex{4, 9}));
  rows.clear();
  EXPECT_TRUE(rows.empty());
  EXPECT_FALSE(rows.span(-3, lo, hi));
  EXPECT_FALSE(rows.span(4, lo, hi));
}

TEST(ChangedRows, ARowAWindowLaterReplacesTheOneThatLeft) {
  ChangedRows rows(10);
  rows.add(CellIndex{2, 1});
  rows.add(CellIndex{12, 4});
  std::int64_t lo = 0, hi = 0;
  EXPECT_FALSE(rows.span(2, lo, hi));
  ASSERT_TRUE(rows.span(12, lo, hi));
  EXPECT_EQ(lo, 4);
  EXPECT_EQ(hi, 4);
  rows.clear();  // bounds span more than the ring: every place cleared
  EXPECT_FALSE(rows.span(12, lo, hi));
}

TEST(ChangedRows, AddsBoxesAndOtherRecords) {
  ChangedRows a(8), b(8);
  a.add(CellBox{{1, 2}, {3, 4}});
  b.add_span(3, -1, 0);
  b.add_span(6, 5, 5);
  a.add(b);
  std::int64_t lo = 0, hi = 0;
  for (std::int64_t x = 1; x <= 2; ++x) {
    ASSERT_TRUE(a.span(x, lo, hi));
    EXPECT_EQ(lo, 2);
    EXPECT_EQ(hi, 4);
  }
  ASSERT_TRUE(a.span(3, lo, hi));
  EXPECT_EQ(lo, -1);
  EXPECT_EQ(hi, 4);
  ASSERT_TRUE(a.span(6, lo, hi));
  EXPECT_EQ(lo, 5);
  EXPECT_FALSE(a.span(5, lo, hi));
  a.add(CellBox{});  // empty: nothing
  EXPECT_EQ(a.bounds().max, (CellIndex{6, 5}));
}

}  // namespace
}  // namespace stridemap
