// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/log_poly.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using mirage::core::log_poly;

namespace {
// |a − b| in units in the last place of b (b ≠ 0).
double ulps(double a, double b) {
    const double ab = std::abs(b);
    return std::abs(a - b) / (std::nextafter(ab, HUGE_VAL) - ab);
}
}  // namespace

TEST(LogPoly, within_two_ulp_of_std_log_over_all_normal_doubles) {
    std::mt19937_64 gen(11);
    std::uniform_real_distribution<double> exponent(-1020.0, 1020.0), near_one(0.5, 2.0);
    double worst = 0;
    for (int i = 0; i < 1'000'000; ++i) {
        const double x = i % 2 ? std::exp2(exponent(gen)) : near_one(gen);
        if (x == 1.0) continue;
        worst = std::max(worst, ulps(log_poly(x), std::log(x)));
    }
    EXPECT_LE(worst, 2.0);
    // Photo-electron counts the intensity map sees: 10 .. 1e6, densely.
    for (double x = 10.0; x < 1e6; x *= 1.0000137)
        ASSERT_LE(ulps(log_poly(x), std::log(x)), 2.0) << x;
}

TEST(LogPoly, exact_at_powers_of_two_and_one) {
    EXPECT_EQ(log_poly(1.0), 0.0);
    for (int e = -1000; e <= 1000; e += 37)
        EXPECT_LE(ulps(log_poly(std::ldexp(1.0, e)), e * std::log(2.0)), 1.0) << e;
    EXPECT_LE(ulps(log_poly(std::numeric_limits<double>::min()),
                   std::log(std::numeric_limits<double>::min())),
              1.0);
    EXPECT_LE(ulps(log_poly(std::numeric_limits<double>::max()),
                   std::log(std::numeric_limits<double>::max())),
              1.0);
}
