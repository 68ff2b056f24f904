// SPDX-License-Identifier: Apache-2.0
// gap_period (mirage-sched-gaps): the period and phase of a spinning thread's gaps, against
// synthetic gap trains whose period is known.
#include "gap_period.hpp"

#include <gtest/gtest.h>

#include <random>

namespace mirage::hil {
namespace {

// One minute of gaps as a virtual machine can show them: 36 µs every 1.000 ms (a hypervisor's
// tick) with 2 µs of jitter, and 40 µs every 4 ms half a period later (a guest's 250 Hz tick).
std::vector<Gap> two_ticks(double period_ns) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> jitter(0.0, 2'000.0);
    std::vector<Gap> g;
    for (int i = 0; i < 60'000; ++i) {
        const auto t = static_cast<std::int64_t>(i * period_ns + 100'000 + jitter(rng));
        g.push_back({t, t + 36'000});
        if (i % 4 == 0) g.push_back({t + 500'000, t + 540'000});
    }
    return g;
}

TEST(GapPeriod, FindsThePeriodAndPhaseOfATick) {
    const GapPeriod p = gap_period(two_ticks(1'000'003.0), 20'000);
    EXPECT_EQ(p.gaps, 75'000u);
    // Spacings per 4 ms: 1, 1, 1 ms and 0.5, 0.5 ms: 3 of 5 near the period.
    EXPECT_NEAR(p.period_ns, 1'000'003.0, 100.0);
    EXPECT_NEAR(p.spacing_share, 0.6, 0.01);
    // 60 000 of 75 000 starts at one phase (within 2 µs, two 50 µs phase bins).
    EXPECT_NEAR(p.phase_share, 0.8, 0.01);
}

TEST(GapPeriod, ShorterGapsAreLeftOut) {
    // Above 38 µs only the 40 µs gaps remain: every 4 ms, all at one phase.
    const GapPeriod p = gap_period(two_ticks(1'000'000.0), 38'000);
    EXPECT_EQ(p.gaps, 15'000u);
    EXPECT_NEAR(p.period_ns, 4'000'000.0, 100.0);
    EXPECT_NEAR(p.spacing_share, 1.0, 1e-3);  // all but the 3.5 sigma tails of the jitter
    EXPECT_NEAR(p.phase_share, 1.0, 1e-9);
}

TEST(GapPeriod, GapsAtRandomTimesHaveNoPreferredPhase) {
    std::mt19937_64 rng(11);
    std::exponential_distribution<double> wait(1.0 / 700'000.0);  // mean spacing 0.7 ms
    std::vector<Gap> g;
    double t = 0;
    for (int i = 0; i < 50'000; ++i) {
        t += 40'000 + wait(rng);
        const auto b = static_cast<std::int64_t>(t);
        g.push_back({b, b + 30'000});
    }
    const GapPeriod p = gap_period(g, 20'000);
    EXPECT_EQ(p.gaps, 50'000u);
    EXPECT_LT(p.spacing_share, 0.05);  // no spacing stands out
    EXPECT_LT(p.phase_share, 0.15);    // two of 20 phase bins: 0.1 expected
}

TEST(GapPeriod, TooFewGapsGiveNoPeriod) {
    const GapPeriod p = gap_period({{0, 50'000}, {1'000'000, 1'050'000}}, 20'000);
    EXPECT_EQ(p.gaps, 2u);
    EXPECT_EQ(p.period_ns, 0.0);
    EXPECT_EQ(p.phase_share, 0.0);
    // Three gaps, but spaced beyond the 100 ms the spacings are binned over.
    const GapPeriod sparse =
        gap_period({{0, 50'000}, {200'000'000, 200'050'000}, {400'000'000, 400'050'000}}, 20'000);
    EXPECT_EQ(sparse.gaps, 3u);
    EXPECT_EQ(sparse.period_ns, 0.0);
}

}  // namespace
}  // namespace mirage::hil
