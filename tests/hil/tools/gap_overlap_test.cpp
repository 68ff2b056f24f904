// SPDX-License-Identifier: Apache-2.0
// delayed_for_all (mirage-sched-gaps --threads): the instants every spinning thread reaches late.
#include "gap_overlap.hpp"

#include <gtest/gtest.h>

namespace mirage::hil {
namespace {

TEST(GapOverlap, OneThreadSumsTheExcessOfEachLongGap) {
    // Gaps of 30, 5 and 50 ns; late = 10: 20 + 0 + 40.
    const std::vector<std::vector<Gap>> g{{{0, 30}, {100, 105}, {200, 250}}};
    EXPECT_EQ(delayed_for_all(g, 10), 60);
    EXPECT_EQ(delayed_for_all(g, 0), 85);
    EXPECT_EQ(delayed_for_all(g, 50), 0);
}

TEST(GapOverlap, TwoThreadsCountOnlyTheInstantsBothReachLate) {
    // Thread 0 delayed by > 10 ns over [0, 90), thread 1 over [50, 110) and [150, 170):
    // together [50, 90) only.
    const std::vector<std::vector<Gap>> g{{{0, 100}, {150, 155}}, {{50, 120}, {150, 180}}};
    EXPECT_EQ(delayed_for_all(g, 10), 40);
    // A third thread never held off: no instant is late for all three.
    auto three = g;
    three.push_back({});
    EXPECT_EQ(delayed_for_all(three, 10), 0);
}

TEST(GapOverlap, DisjointGapsNeverOverlapAndOneIntervalMaySpanSeveral) {
    const std::vector<std::vector<Gap>> disjoint{{{0, 100}}, {{200, 300}}};
    EXPECT_EQ(delayed_for_all(disjoint, 0), 0);
    // One long gap of thread 0 spans two of thread 1: [10, 40) + [60, 90) with late = 0.
    const std::vector<std::vector<Gap>> spans{{{0, 100}}, {{10, 40}, {60, 90}}};
    EXPECT_EQ(delayed_for_all(spans, 0), 60);
    EXPECT_EQ(delayed_for_all({}, 0), 0);
}

}  // namespace
}  // namespace mirage::hil
