// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/exp_poly.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

using mirage::core::exp_poly;

namespace {
// Distance in units in the last place between two positive finite doubles.
double ulps(double a, double b) { return std::abs(a - b) / (std::nextafter(b, HUGE_VAL) - b); }
[[gnu::noinline]] double one_call(double x) { return exp_poly(x); }
}  // namespace

TEST(ExpPoly, within_two_ulp_of_std_exp_over_the_whole_range) {
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<double> wide(-708.0, 709.0), narrow(-1.0, 1.0);
    double worst = 0;
    for (int i = 0; i < 1'000'000; ++i) {
        const double x = i % 2 ? wide(gen) : narrow(gen);
        worst = std::max(worst, ulps(exp_poly(x), std::exp(x)));
    }
    EXPECT_LE(worst, 2.0);
    // Transmission exponents: −2αR for α up to 0.1 /m (dense fog) and R up to 2 km.
    for (double x = -400.0; x <= 0.0; x += 1e-3)
        ASSERT_LE(ulps(exp_poly(x), std::exp(x)), 2.0) << x;
}

TEST(ExpPoly, exact_at_zero_and_saturates_outside_the_normal_range) {
    EXPECT_EQ(exp_poly(0.0), 1.0);
    EXPECT_EQ(exp_poly(-0.0), 1.0);
    EXPECT_EQ(exp_poly(-708.5), 0.0);
    EXPECT_EQ(exp_poly(-1e300), 0.0);
    EXPECT_EQ(exp_poly(-HUGE_VAL), 0.0);
    EXPECT_EQ(exp_poly(710.0), HUGE_VAL);
    EXPECT_EQ(exp_poly(HUGE_VAL), HUGE_VAL);
    EXPECT_TRUE(std::isnan(exp_poly(std::numeric_limits<double>::quiet_NaN())));
    EXPECT_LE(ulps(exp_poly(-708.0), std::exp(-708.0)), 2.0);
    EXPECT_LE(ulps(exp_poly(709.0), std::exp(709.0)), 2.0);
}

// The pipeline calls exp_poly in loops the compiler vectorises (docs/dependencies.md): such a loop
// gives the bits of one call at a time, the range checks and NaN included.
TEST(ExpPoly, a_vectorised_loop_gives_the_bits_of_single_calls) {
    std::mt19937_64 gen(3);
    std::uniform_real_distribution<double> wide(-800.0, 800.0);
    std::vector<double> x{0.0,
                          -0.0,
                          -708.0,
                          -708.5,
                          709.0,
                          710.0,
                          -1e300,
                          1e300,
                          HUGE_VAL,
                          -HUGE_VAL,
                          std::numeric_limits<double>::quiet_NaN()};
    for (int i = 0; i < 100'000; ++i) x.push_back(wide(gen));
    std::vector<double> y(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = exp_poly(x[i]);
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double s = one_call(x[i]);
        if (std::isnan(s)) {
            ASSERT_TRUE(std::isnan(y[i])) << x[i];
            continue;
        }
        ASSERT_EQ(std::bit_cast<std::uint64_t>(y[i]), std::bit_cast<std::uint64_t>(s)) << x[i];
    }
}
