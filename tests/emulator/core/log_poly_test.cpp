// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/log_poly.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

using mirage::core::log_poly;

namespace {
// |a − b| in units in the last place of b (b ≠ 0).
double ulps_any_sign(double a, double b) {
    const double ab = std::abs(b);
    return std::abs(a - b) / (std::nextafter(ab, HUGE_VAL) - ab);
}
[[gnu::noinline]] double one_log_call(double x) { return log_poly(x); }
}  // namespace

TEST(LogPoly, within_two_ulp_of_std_log_over_all_normal_doubles) {
    std::mt19937_64 gen(11);
    std::uniform_real_distribution<double> exponent(-1020.0, 1020.0), near_one(0.5, 2.0);
    double worst = 0;
    for (int i = 0; i < 1'000'000; ++i) {
        const double x = i % 2 ? std::exp2(exponent(gen)) : near_one(gen);
        if (x == 1.0) continue;
        worst = std::max(worst, ulps_any_sign(log_poly(x), std::log(x)));
    }
    EXPECT_LE(worst, 2.0);
    // Photo-electron counts the intensity map sees: 10 .. 1e6, densely.
    for (double x = 10.0; x < 1e6; x *= 1.0000137)
        ASSERT_LE(ulps_any_sign(log_poly(x), std::log(x)), 2.0) << x;
}

TEST(LogPoly, exact_at_powers_of_two_and_one) {
    EXPECT_EQ(log_poly(1.0), 0.0);
    for (int e = -1000; e <= 1000; e += 37)
        EXPECT_LE(ulps_any_sign(log_poly(std::ldexp(1.0, e)), e * std::log(2.0)), 1.0) << e;
    EXPECT_LE(ulps_any_sign(log_poly(std::numeric_limits<double>::min()),
                            std::log(std::numeric_limits<double>::min())),
              1.0);
    EXPECT_LE(ulps_any_sign(log_poly(std::numeric_limits<double>::max()),
                            std::log(std::numeric_limits<double>::max())),
              1.0);
}

// The intensity map calls log_poly in a loop the compiler vectorises: it gives the bits of one
// call at a time over the positive normal doubles.
TEST(LogPoly, a_vectorised_loop_gives_the_bits_of_single_calls) {
    std::mt19937_64 gen(5);
    std::uniform_real_distribution<double> exponent(-1020.0, 1020.0);
    std::vector<double> x{1.0, 0.5, 2.0, std::numeric_limits<double>::min(),
                          std::numeric_limits<double>::max()};
    for (int i = 0; i < 100'000; ++i) x.push_back(std::exp2(exponent(gen)));
    std::vector<double> y(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = log_poly(x[i]);
    for (std::size_t i = 0; i < x.size(); ++i)
        ASSERT_EQ(std::bit_cast<std::uint64_t>(y[i]),
                  std::bit_cast<std::uint64_t>(one_log_call(x[i])))
            << x[i];
}
