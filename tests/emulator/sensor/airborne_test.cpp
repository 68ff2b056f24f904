// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/airborne.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "mirage/core/error.hpp"
#include "mirage/sensor/sensor.hpp"
#include "test_units.hpp"

namespace mirage::sensor {
namespace {

using mirage::test::kDeg;

std::vector<PulseSpec> fire(const ScanPattern& s, std::uint64_t first, std::size_t n) {
    std::vector<PulseSpec> out(n);
    s.pulses(first, n, out.data());
    return out;
}

// Across-track angle from the direction (+ right), degrees.
double across_deg(const PulseSpec& p) {
    return std::atan2(-double(p.dir.y()), -double(p.dir.z())) / kDeg;
}

TEST(AirbornePattern, presets_are_single_beam_airborne_with_groups_of_16) {
    for (const char* name : {"als-mirror", "als-mirror-sine", "als-polygon", "als-palmer"}) {
        const auto m = preset(name);
        EXPECT_TRUE(m.airborne) << name;
        EXPECT_EQ(m.scan->channels(), 1u) << name;
        EXPECT_EQ(m.scan->group_size(), 16u) << name;
        EXPECT_DOUBLE_EQ(m.beam.wavelength_m, 1064e-9) << name;
        EXPECT_DOUBLE_EQ(m.beam.divergence_rad, 0.5e-3) << name;
        EXPECT_DOUBLE_EQ(m.receiver.max_range_m, 2000.0) << name;
        EXPECT_DOUBLE_EQ(m.receiver.min_range_m, 10.0) << name;
    }
    const auto mirror = preset("als-mirror");
    EXPECT_DOUBLE_EQ(mirror.scan->pulse_rate_hz(), 500e3);
    EXPECT_EQ(mirror.scan->pulse_count(core::Nanos(1'000'000'000)), 500'000u);
    EXPECT_EQ(mirror.scan->pulse_count(core::Nanos(2'001)), 2u);  // t = 0, 2000 ns
}

TEST(AirbornePattern, sawtooth_is_linear_in_time_and_turns_at_half_fov) {
    // 500 kHz, 50 Hz mirror = 100 lines/s → 5000 pulses per line, ±20°.
    const auto m = preset("als-mirror");
    const auto p = fire(*m.scan, 0, 20'000);
    for (std::size_t k = 0; k < p.size(); ++k) {
        const double phase = double(k % 10'000) / 10'000.0;
        const double expect = phase < 0.5 ? -20.0 + 80.0 * phase : 20.0 - 80.0 * (phase - 0.5);
        ASSERT_NEAR(p[k].scan_angle_deg, expect, 1e-4) << k;
        ASSERT_NEAR(across_deg(p[k]), expect, 1e-4) << k;
        ASSERT_EQ(p[k].t_ns, std::int64_t(2000 * k));
        ASSERT_EQ(p[k].scan_direction, phase < 0.5 ? 1 : 0) << k;
        const bool last_of_line = (k + 1) % 5000 == 0;
        ASSERT_EQ(p[k].edge_of_flight_line, last_of_line ? 1 : 0) << k;
        ASSERT_LE(std::abs(p[k].scan_angle_deg), 20.0f);
    }
    EXPECT_FLOAT_EQ(p[0].scan_angle_deg, -20.0f);
    EXPECT_FLOAT_EQ(p[5000].scan_angle_deg, 20.0f);
    EXPECT_FLOAT_EQ(p[10'000].scan_angle_deg, -20.0f);
    // Constant angular speed: equal steps of 40°/5000 everywhere on a line.
    EXPECT_NEAR(p[1234].scan_angle_deg - p[1233].scan_angle_deg, 0.008, 1e-5);
    EXPECT_NEAR(p[7234].scan_angle_deg - p[7233].scan_angle_deg, -0.008, 1e-5);
    // Nadir pulse points straight down; +angle points right (−y).
    EXPECT_NEAR(p[2500].dir.z(), -1.0, 1e-7);
    EXPECT_LT(p[4000].dir.y(), 0.0f);
    EXPECT_NEAR(p[4000].azimuth_deg, 90.0, 1e-4);
    // The direction is (0, −sin θ, −cos θ) of the scan angle to float precision (the generator
    // evaluates sin and cos by series): within one float ulp of the library's values.
    for (std::size_t k = 0; k < p.size(); ++k) {
        const double th = double(p[k].scan_angle_deg) * kDeg;
        ASSERT_EQ(p[k].dir.x(), 0.0f) << k;
        ASSERT_NEAR(p[k].dir.y(), -std::sin(th), 6e-8 * std::abs(std::sin(th)) + 1e-7) << k;
        ASSERT_NEAR(p[k].dir.z(), -std::cos(th), 6e-8) << k;
        ASSERT_FLOAT_EQ(p[k].azimuth_deg, th > 0 ? 90.0f : th < 0 ? 270.0f : 0.0f) << k;
    }
}

TEST(AirbornePattern, sine_reaches_half_fov_and_flips_direction_at_the_turns) {
    const auto m = preset("als-mirror-sine");
    const auto p = fire(*m.scan, 0, 10'000);  // one mirror period
    float hi = -90, lo = 90;
    for (std::size_t k = 0; k < p.size(); ++k) {
        const double expect = 20.0 * std::sin(2.0 * std::numbers::pi * double(k) / 10'000.0);
        ASSERT_NEAR(p[k].scan_angle_deg, expect, 1e-4) << k;
        hi = std::max(hi, p[k].scan_angle_deg);
        lo = std::min(lo, p[k].scan_angle_deg);
    }
    EXPECT_FLOAT_EQ(hi, 20.0f);  // k = 2500
    EXPECT_FLOAT_EQ(lo, -20.0f);
    EXPECT_EQ(p[100].scan_direction, 1);
    EXPECT_EQ(p[2499].scan_direction, 1);
    EXPECT_EQ(p[2501].scan_direction, 0);
    EXPECT_EQ(p[7501].scan_direction, 1);
    EXPECT_EQ(p[2499].edge_of_flight_line, 1);  // line changes at the turn k = 2500
    EXPECT_EQ(p[7499].edge_of_flight_line, 1);
    int edges = 0;
    for (const auto& s : p) edges += s.edge_of_flight_line;
    EXPECT_EQ(edges, 2);
}

TEST(AirbornePattern, polygon_sweeps_one_way_and_jumps_back) {
    // 1 MHz, 4 facets × 50 rev/s = 200 lines/s → 5000 pulses per line over 60°.
    const auto m = preset("als-polygon");
    const auto p = fire(*m.scan, 0, 10'000);
    for (std::size_t k = 0; k < p.size(); ++k) {
        const double expect = -30.0 + 60.0 * double(k % 5000) / 5000.0;
        ASSERT_NEAR(p[k].scan_angle_deg, expect, 1e-4) << k;
        ASSERT_EQ(p[k].scan_direction, 1);
        ASSERT_EQ(p[k].edge_of_flight_line, (k + 1) % 5000 == 0 ? 1 : 0) << k;
    }
    EXPECT_LT(p[5000].scan_angle_deg, p[4999].scan_angle_deg);  // fly-back
}

TEST(AirbornePattern, palmer_keeps_a_constant_angle_from_nadir) {
    // 1 MHz, 50 rev/s → 20 000 pulses per revolution, cone half-angle 20°.
    const auto m = preset("als-palmer");
    const auto p = fire(*m.scan, 0, 20'000);
    for (const auto& s : p) ASSERT_NEAR(std::acos(-double(s.dir.z())) / kDeg, 20.0, 1e-4);
    EXPECT_NEAR(p[0].azimuth_deg, 0.0, 1e-4);  // forward
    EXPECT_GT(p[0].dir.x(), 0.3f);
    EXPECT_NEAR(p[5000].azimuth_deg, 90.0, 1e-3);  // right
    EXPECT_NEAR(p[5000].scan_angle_deg, 20.0, 1e-4);
    EXPECT_NEAR(p[10'000].azimuth_deg, 180.0, 1e-3);  // backward
    EXPECT_LT(p[10'000].dir.x(), -0.3f);
    EXPECT_EQ(p[1000].scan_direction, 1);    // forward arc moves right
    EXPECT_EQ(p[11'000].scan_direction, 0);  // backward arc moves left
    EXPECT_EQ(p[4999].edge_of_flight_line, 1);
    EXPECT_EQ(p[14'999].edge_of_flight_line, 1);
    int edges = 0;
    for (const auto& s : p) edges += s.edge_of_flight_line;
    EXPECT_EQ(edges, 2);
}

TEST(AirbornePattern, tilt_pitches_the_pattern_forward) {
    AirborneConfig c;
    c.kind = AirborneKind::Sawtooth;
    c.prf_hz = 100e3;
    c.scan_rate_hz = 10;
    c.fov_deg = 40;
    c.tilt_deg = 10;
    const auto s = make_airborne_pattern(c);
    const auto nadir = fire(*s, 2500, 1)[0];  // mirror at 0°
    EXPECT_NEAR(nadir.scan_angle_deg, 0.0, 1e-5);
    EXPECT_NEAR(nadir.dir.x(), std::sin(10 * kDeg), 1e-6);
    EXPECT_NEAR(nadir.dir.z(), -std::cos(10 * kDeg), 1e-6);
    EXPECT_NEAR(nadir.azimuth_deg, 0.0, 1e-4);
}

TEST(AirbornePattern, rejects_bad_configurations) {
    AirborneConfig c;
    c.fov_deg = 0;
    EXPECT_THROW(make_airborne_pattern(c), ConfigError);
    c.fov_deg = 40;
    c.prf_hz = -1;
    EXPECT_THROW(make_airborne_pattern(c), ConfigError);
    c.prf_hz = 1e5;
    c.kind = AirborneKind::Polygon;
    c.facets = 0;
    EXPECT_THROW(make_airborne_pattern(c), ConfigError);
}

}  // namespace
}  // namespace mirage::sensor
