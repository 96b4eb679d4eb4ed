// ChangedRows (core/changed_rows.hpp): per-row spans of changed cells kept
// in a ring of one window's rows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

#include "stridemap/core/changed_rows.hpp"

namespace stridemap {
namespace {

// The same bounds and the same span in every row around `first`: a record
// merged at once against one built row by row.
void expect_same_rows(const ChangedRows& at_once, const ChangedRows& one_by_one, std::int64_t first) {
  EXPECT_EQ(at_once.bounds().min, one_by_one.bounds().min);
  EXPECT_EQ(at_once.bounds().max, one_by_one.bounds().max);
  for (std::int64_t x = first - 12; x < first + 24; ++x) {
    std::int64_t lo_a = 0, hi_a = 0, lo_b = 0, hi_b = 0;
    const bool a = at_once.span(x, lo_a, hi_a), b = one_by_one.span(x, lo_b, hi_b);
    ASSERT_EQ(a, b) << "row " << x;
    if (a) {
      EXPECT_EQ(lo_a, lo_b) << "row " << x;
      EXPECT_EQ(hi_a, hi_b) << "row " << x;
    }
  }
}

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

// The mapper's spans of one scan, added at once, must leave exactly what
// adding them row by row does: rows across the ring's wrap and below zero,
// rows without a span, and rows already holding a span or an older row.
TEST(ChangedRows, SpansAddedAtOnceMatchSpansAddedRowByRow) {
  for (const std::int64_t first : {-13, -1, 0, 7, 98}) {
    ChangedRows one_by_one(10), at_once(10);
    for (ChangedRows* rows : {&one_by_one, &at_once}) {
      rows->add_span(first + 1, 3, 4);    // widened below
      rows->add_span(first + 2 - 10, 0, 9);  // an older row at a place reused below
    }
    const std::int32_t lo[] = {5, std::numeric_limits<std::int32_t>::max(), -2, 0, 6, 1, 2, 3, 4, 5, 6, 7};
    const std::int32_t hi[] = {8, -1, 1, 0, 6, 9, 2, 8, 4, 7, 6, 9};
    const std::size_t count = sizeof lo / sizeof lo[0];  // more than the ring: later rows replace earlier ones
    const std::int64_t y0 = -40;
    for (std::size_t k = 0; k < count; ++k) {
      one_by_one.add_span(first + static_cast<std::int64_t>(k), y0 + lo[k], y0 + hi[k]);
    }
    at_once.add_spans(first, count, lo, hi, y0);
    EXPECT_EQ(at_once.bounds().min, one_by_one.bounds().min) << first;
    EXPECT_EQ(at_once.bounds().max, one_by_one.bounds().max) << first;
    for (std::int64_t x = first - 12; x < first + 24; ++x) {
      std::int64_t lo_a = 0, hi_a = 0, lo_b = 0, hi_b = 0;
      const bool a = at_once.span(x, lo_a, hi_a), b = one_by_one.span(x, lo_b, hi_b);
      ASSERT_EQ(a, b) << "row " << x << ", first " << first;
      if (a) {
        EXPECT_EQ(lo_a, lo_b) << "row " << x << ", first " << first;
        EXPECT_EQ(hi_a, hi_b) << "row " << x << ", first " << first;
      }
    }
  }
  ChangedRows none(10);
  const std::int32_t lo[] = {1}, hi[] = {0};
  none.add_spans(3, 1, lo, hi, 0);
  EXPECT_TRUE(none.empty());
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

TEST(ChangedRows, AnotherRecordAddedAtOnceMatchesItsSpansAddedRowByRow) {
  // Rings of other sizes, rows either side of 0 and across the rings' wrap,
  // a row replaced in the other record and one already in this one.
  for (const int other_rows : {4, 7, 10}) {
    for (const std::int64_t first : {-13, -1, 0, 7, 98}) {
      ChangedRows other(other_rows), at_once(7), one_by_one(7);
      for (std::int64_t k = 0; k < 9; ++k) other.add_span(first + k, -k, 2 * k - 3);
      other.add_span(first + 8 - other_rows, 1, 1);  // replaced: not in other any more
      for (ChangedRows* rows : {&at_once, &one_by_one}) rows->add_span(first + 7, -20, -19);
      at_once.add(other);
      std::int64_t lo = 0, hi = 0;  // other's last rows() rows, those it can hold
      for (std::int64_t x = std::max(other.bounds().min.x, other.bounds().max.x - other_rows + 1);
           x <= other.bounds().max.x; ++x) {
        if (other.span(x, lo, hi)) one_by_one.add_span(x, lo, hi);
      }
      SCOPED_TRACE("first " + std::to_string(first) + ", other's rows " + std::to_string(other_rows));
      expect_same_rows(at_once, one_by_one, first);
    }
  }
}

TEST(ChangedRows, AnotherRecordThatReplacedNoRowAddsItsOwnBounds) {
  // Fewer rows than the other ring holds: its bounds are its spans' box,
  // taken whole; into a ring larger or smaller than the other's.
  for (const int rows_here : {5, 7, 16}) {
    for (const std::int64_t first : {-13, -1, 0, 7, 98}) {
      ChangedRows other(12), at_once(rows_here), one_by_one(rows_here);
      for (std::int64_t k = 0; k < 9; ++k) {
        if (k != 4) other.add_span(first + k, -k, 2 * k - 3);  // a gap among the rows
      }
      at_once.add(other);
      std::int64_t lo = 0, hi = 0;
      for (std::int64_t x = other.bounds().min.x; x <= other.bounds().max.x; ++x) {
        if (other.span(x, lo, hi)) one_by_one.add_span(x, lo, hi);
      }
      SCOPED_TRACE("first " + std::to_string(first) + ", rows here " + std::to_string(rows_here));
      expect_same_rows(at_once, one_by_one, first);
    }
  }
}

}  // namespace
}  // namespace stridemap
