// The bench's medians (bench/median.h): the figure every timing and every ratio to Embree reports.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "bench/median.h"

using namespace ht;

TEST(BenchMedian, UpperMiddleOfTheSortedValues) {
    EXPECT_EQ(median({}), 0.0);
    EXPECT_EQ(median({3.0}), 3.0);
    EXPECT_EQ(median({5.0, 1.0, 4.0}), 4.0);
    EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 3.0);  // the upper of the two middle values
}

TEST(BenchMedian, PairedSpeedupIsTheMedianOfThePairsRatios) {
    // ours twice as fast in every pair while the machine slows down 3x over the run: every pair says 2
    const std::vector<double> theirs{2.0, 3.0, 4.0, 5.0, 6.0}, ours{1.0, 1.5, 2.0, 2.5, 3.0};
    EXPECT_DOUBLE_EQ(paired_speedup(theirs, ours), 2.0);
    // one pair disturbed (ours slow once) moves the median of five by nothing
    EXPECT_DOUBLE_EQ(paired_speedup(theirs, {1.0, 1.5, 8.0, 2.5, 3.0}), 2.0);
    // a slower tracer gives a ratio below 1
    EXPECT_DOUBLE_EQ(paired_speedup({1.0, 1.0, 1.0}, {4.0, 4.0, 4.0}), 0.25);
}

TEST(BenchMedian, PairedSpeedupDropsPairsWithoutATimeOnBothSides) {
    const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
    EXPECT_DOUBLE_EQ(paired_speedup({2.0, 0.0, 9.0, nan, 3.0}, {1.0, 1.0, inf, 1.0, 1.0}), 3.0);
    EXPECT_EQ(paired_speedup({0.0, -1.0}, {1.0, 1.0}), 0.0);
    EXPECT_EQ(paired_speedup({}, {}), 0.0);
    // pairs only as far as both lists go
    EXPECT_DOUBLE_EQ(paired_speedup({2.0, 2.0, 2.0, 100.0}, {1.0, 1.0, 1.0}), 2.0);
}
