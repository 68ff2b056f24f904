// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/rounding.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

using mirage::core::round_half_away;

// Same value as std::round (halfway away from zero) on the cases where tricks usually fail.
TEST(RoundHalfAway, matches_std_round_on_ties_neighbours_and_extremes) {
    const double largest_below_half = std::nextafter(0.5, 0.0);
    const double cases[] = {0.0,
                            -0.0,
                            0.5,
                            -0.5,
                            1.5,
                            -1.5,
                            2.5,
                            -2.5,
                            largest_below_half,
                            -largest_below_half,
                            std::nextafter(0.5, 1.0),
                            std::nextafter(1.5, 1.0),
                            std::nextafter(1.5, 2.0),
                            4503599627370495.5,  // 2^52 − ½: the last halves
                            -4503599627370495.5,
                            4503599627370497.0,  // beyond 2^52: integers only
                            9007199254740993.0,
                            2147483647.4,
                            -2147483648.4,
                            1e300,
                            -1e300,
                            std::numeric_limits<double>::denorm_min(),
                            std::numeric_limits<double>::infinity(),
                            -std::numeric_limits<double>::infinity()};
    for (double v : cases) EXPECT_EQ(round_half_away(v), std::round(v)) << v;
    EXPECT_TRUE(std::isnan(round_half_away(std::numeric_limits<double>::quiet_NaN())));
}

TEST(RoundHalfAway, matches_llround_on_a_million_coordinates_and_every_half_step) {
    // LAS quantisation: (anchor shift + local) / 1 mm at UTM magnitudes, and exact halves.
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<double> u(-5e9, 5e9);
    for (int i = 0; i < 1'000'000; ++i) {
        const double v = u(gen);
        ASSERT_EQ(static_cast<long long>(round_half_away(v)), std::llround(v)) << v;
    }
    for (long long k = -100'000; k <= 100'000; ++k) {
        const double half = static_cast<double>(k) + 0.5;
        ASSERT_EQ(static_cast<long long>(round_half_away(half)), std::llround(half)) << half;
    }
}
