// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "mirage/physics/radiometry.hpp"

using mirage::physics::IntensityCalibration;

TEST(IntensityCalibration, endpoints_clamp_to_zero_and_full_scale) {
    const IntensityCalibration cal{10.0, 1e6};
    for (double n : {-5.0, 0.0, 1.0, 9.999, 10.0, std::numeric_limits<double>::quiet_NaN()}) {
        EXPECT_EQ(cal.to_u16(n), 0) << n;
        EXPECT_EQ(cal.to_u8(n), 0) << n;
    }
    for (double n : {1e6, 1e6 + 1.0, 1e9, std::numeric_limits<double>::infinity()}) {
        EXPECT_EQ(cal.to_u16(n), 65535) << n;
        EXPECT_EQ(cal.to_u8(n), 255) << n;
    }
    // Geometric midpoint is half scale (log map): 10^3.5 → 0.5·65535 = 32767.5 (either neighbour).
    EXPECT_NEAR(cal.to_u16(std::pow(10.0, 3.5)), 32767.5, 0.5);
    EXPECT_NEAR(cal.to_u8(std::pow(10.0, 3.5)), 127.5, 0.5);
    // One decade of five → 0.2 of full scale.
    EXPECT_EQ(cal.to_u16(100.0), 13107);
    EXPECT_EQ(cal.to_u8(100.0), 51);
}

TEST(IntensityCalibration, is_monotonic_over_the_whole_range) {
    const IntensityCalibration cal{10.0, 1e6};
    std::uint16_t prev16 = 0;
    std::uint8_t prev8 = 0;
    int rises = 0;
    for (int i = 0; i <= 4000; ++i) {
        const double n = std::pow(10.0, -1.0 + 8.0 * i / 4000.0);  // 0.1 .. 1e7
        const std::uint16_t v16 = cal.to_u16(n);
        const std::uint8_t v8 = cal.to_u8(n);
        ASSERT_GE(v16, prev16) << n;
        ASSERT_GE(v8, prev8) << n;
        if (v16 > prev16) ++rises;
        prev16 = v16;
        prev8 = v8;
    }
    EXPECT_GT(rises, 2000);  // strictly increasing across the calibrated decades
}

TEST(IntensityCalibration, degenerate_range_is_a_step_at_n_max) {
    const IntensityCalibration cal{100.0, 100.0};
    EXPECT_EQ(cal.to_u16(99.0), 0);
    EXPECT_EQ(cal.to_u16(100.0), 65535);
    EXPECT_EQ(cal.to_u8(1e4), 255);
}

// The batched map the pipeline uses gives to_u16's value for every input: across the range, at
// both ends, outside it, for NaN, and for the degenerate (step) calibrations.
TEST(IntensityCalibration, to_u16_many_equals_to_u16) {
    std::vector<double> n = {0.0, -1.0,           std::nan(""), 10.0,     10.000001,
                             1e6, 1e6 * 0.999999, 2e6,          HUGE_VAL, 5.0};
    for (double x = 9.0; x < 1.2e6; x *= 1.000037) n.push_back(x);
    for (const IntensityCalibration cal :
         {IntensityCalibration{10.0, 1e6}, IntensityCalibration{1.0, 2.0},
          IntensityCalibration{0.0, 1e6}, IntensityCalibration{5.0, 5.0}}) {
        std::vector<std::uint16_t> got(n.size());
        cal.to_u16_many(n.data(), n.size(), got.data());
        std::size_t differ = 0;
        for (std::size_t j = 0; j < n.size(); ++j) differ += got[j] != cal.to_u16(n[j]);
        EXPECT_EQ(differ, 0u) << cal.n_min << " " << cal.n_max;
    }
}
