// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/spinning.hpp"

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

std::vector<PulseSpec> fire(const SensorModel& m, std::uint64_t first, std::size_t n) {
    std::vector<PulseSpec> out(n);
    m.scan->pulses(first, n, out.data());
    return out;
}

double elevation_deg(const PulseSpec& p) { return std::asin(double(p.dir.z())) / kDeg; }

TEST(SpinningPattern, pulse_rates_match_the_firing_tables) {
    EXPECT_NEAR(preset("vlp16").scan->pulse_rate_hz(), 289'352.0, 1.0);  // 16 / 55.296 µs
    EXPECT_NEAR(preset("vlp16-hires").scan->pulse_rate_hz(), 16 / 55.296e-6, 1e-6);
    EXPECT_NEAR(preset("vlp32c").scan->pulse_rate_hz(), 32 / 55.296e-6, 1e-6);
    EXPECT_NEAR(preset("hdl32e").scan->pulse_rate_hz(), 32 / 46.08e-6, 1e-6);
    EXPECT_NEAR(preset("hdl64e-s3").scan->pulse_rate_hz(), 64 / 48e-6, 1e-6);
    EXPECT_DOUBLE_EQ(preset("os1-64-1024x10").scan->pulse_rate_hz(), 655'360.0);
    EXPECT_DOUBLE_EQ(preset("os1-128-2048x20").scan->pulse_rate_hz(), 128.0 * 2048 * 20);
}

TEST(SpinningPattern, pulse_count_of_one_second_matches_the_rate) {
    // VLP-16: 18 084 full sequences end at 999 972 864 ns; the next one fires lasers at
    // 0, 2.304, …, 25.344 µs before 1 s (12 of them): 18 084·16 + 12 = 289 356.
    const auto vlp16 = preset("vlp16");
    EXPECT_EQ(vlp16.scan->pulse_count(core::Nanos(1'000'000'000)), 289'356u);
    for (const auto& name : preset_names()) {
        const auto m = preset(name);
        const double count = double(m.scan->pulse_count(core::Nanos(1'000'000'000)));
        EXPECT_NEAR(count, m.scan->pulse_rate_hz(), m.scan->channels() + 1.0) << name;
    }
    EXPECT_EQ(vlp16.scan->pulse_count(core::Nanos(0)), 0u);
    EXPECT_EQ(vlp16.scan->pulse_count(core::Nanos(1)), 1u);  // pulse 0 at t = 0
}

TEST(SpinningPattern, pulse_count_agrees_with_firing_times) {
    for (const char* name : {"vlp16", "hdl64e-s3", "os1-64-1024x10", "vlp32c"}) {
        const auto m = preset(name);
        for (std::int64_t d : {1'000, 55'296, 97'656, 97'657, 1'234'567, 100'000'000}) {
            const std::uint64_t n = m.scan->pulse_count(core::Nanos(d));
            const auto around = fire(m, n - 1, 2);
            EXPECT_LT(around[0].t_ns, d) << name << " " << d;
            EXPECT_GE(around[1].t_ns, d) << name << " " << d;
        }
    }
}

TEST(SpinningPattern, vlp16_azimuth_step_between_sequences_is_0_19906_deg_at_600_rpm) {
    const auto m = preset("vlp16");
    const auto* spin = dynamic_cast<const SpinningPattern*>(m.scan.get());
    ASSERT_NE(spin, nullptr);
    EXPECT_NEAR(spin->azimuth_step_deg(), 360.0 * 10 * 55.296e-6, 1e-12);
    EXPECT_NEAR(spin->azimuth_step_deg(), 0.19906, 1e-5);
    EXPECT_DOUBLE_EQ(spin->rpm(), 600.0);
    const auto p = fire(m, 16 * 100, 32);
    for (int c = 0; c < 16; ++c) {
        EXPECT_NEAR(p[16 + c].azimuth_deg - p[c].azimuth_deg, 0.1990656, 2e-4);
        EXPECT_EQ(p[16 + c].t_ns - p[c].t_ns, 55'296);
    }
}

TEST(SpinningPattern, vlp16_elevations_and_firing_offsets_follow_the_manual_table) {
    const double table[16] = {-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15};
    const auto p = fire(preset("vlp16"), 0, 16);
    for (int c = 0; c < 16; ++c) {
        EXPECT_EQ(p[c].channel, c);
        EXPECT_FLOAT_EQ(p[c].scan_angle_deg, float(table[c]));
        EXPECT_NEAR(elevation_deg(p[c]), table[c], 1e-4);
        EXPECT_EQ(p[c].t_ns, 2304 * c);  // 2.304 µs spacing
        // Azimuth: 360°·10 Hz·t, clockwise.
        EXPECT_NEAR(p[c].azimuth_deg, 3600.0 * 2304e-9 * c, 1e-5);
    }
}

TEST(SpinningPattern, direction_is_clockwise_from_forward) {
    // Sequence at azimuth ≈ 90° (quarter turn): dir points right (−y).
    const auto m = preset("vlp16");
    const std::uint64_t seq = std::uint64_t(std::llround(90.0 / 0.1990656));
    const auto p = fire(m, seq * 16 + 15, 1)[0];  // channel 15, +15°
    const double az = p.azimuth_deg * kDeg, el = 15.0 * kDeg;
    EXPECT_NEAR(p.azimuth_deg, 90.0, 0.2);
    EXPECT_NEAR(p.dir.x(), std::cos(el) * std::cos(az), 1e-6);
    EXPECT_NEAR(p.dir.y(), -std::cos(el) * std::sin(az), 1e-6);
    EXPECT_LT(p.dir.y(), -0.9);
    EXPECT_NEAR(p.dir.z(), std::sin(el), 1e-6);
    EXPECT_NEAR(p.dir.norm(), 1.0, 1e-6);
}

TEST(SpinningPattern, pulses_are_a_pure_function_of_the_index) {
    for (const auto& name : preset_names()) {
        const auto m = preset(name);
        for (std::uint64_t first :
             {std::uint64_t(0), std::uint64_t(12'345), std::uint64_t(1'000'000'007)}) {
            const std::size_t n = 3 * m.scan->group_size() + 5;
            const auto batch = fire(m, first, n);
            for (std::size_t i = 0; i < n; ++i) {
                const auto one = fire(m, first + i, 1)[0];
                ASSERT_EQ(one.t_ns, batch[i].t_ns) << name << " k=" << first + i;
                ASSERT_EQ(one.dir, batch[i].dir) << name;
                ASSERT_EQ(one.channel, batch[i].channel) << name;
                ASSERT_EQ(one.azimuth_deg, batch[i].azimuth_deg) << name;
                ASSERT_EQ(one.scan_angle_deg, batch[i].scan_angle_deg) << name;
                ASSERT_EQ(one.scan_direction, batch[i].scan_direction) << name;
                ASSERT_EQ(one.edge_of_flight_line, batch[i].edge_of_flight_line) << name;
            }
        }
    }
}

TEST(SpinningPattern, firing_times_never_decrease_and_start_at_zero) {
    for (const auto& name : preset_names()) {
        const auto m = preset(name);
        EXPECT_EQ(fire(m, 0, 1)[0].t_ns, 0) << name;
        for (std::uint64_t first : {std::uint64_t(0), std::uint64_t(987'654'321)}) {
            const auto p = fire(m, first, 20'000);
            for (std::size_t i = 1; i < p.size(); ++i)
                ASSERT_LE(p[i - 1].t_ns, p[i].t_ns) << name << " k=" << first + i;
            for (const auto& s : p) {
                ASSERT_GE(s.azimuth_deg, 0.0f) << name;
                ASSERT_LT(s.azimuth_deg, 360.0f) << name;
            }
        }
    }
}

TEST(SpinningPattern, hdl64e_upper_and_lower_lasers_fire_together_within_48_us) {
    const auto m = preset("hdl64e-s3");
    EXPECT_EQ(m.scan->channels(), 64u);
    EXPECT_EQ(m.scan->group_size(), 64u);
    const auto p = fire(m, 0, 64);
    const std::int64_t within[4] = {0, 1260, 2460, 3660};  // VeloView T reversed
    for (int i = 0; i < 32; ++i) {
        const auto& upper = p[2 * i];
        const auto& lower = p[2 * i + 1];
        EXPECT_EQ(upper.channel, i);
        EXPECT_EQ(lower.channel, 32 + i);
        EXPECT_EQ(upper.t_ns, lower.t_ns);
        EXPECT_EQ(upper.t_ns, 6000 * (i / 4) + within[i % 4]);
        EXPECT_LT(upper.t_ns, 48'000);
    }
    // Calibration 64e_s3-xiesc: laser 0 vert −0.12618 rad, rot −0.07648 rad → az offset +4.382°.
    EXPECT_NEAR(p[0].scan_angle_deg, -0.1261818455292898 / kDeg, 1e-4);
    EXPECT_NEAR(p[0].azimuth_deg, 0.07648247457737148 / kDeg, 1e-4);
    float lo = 90, hi = -90;
    for (const auto& s : p) {
        lo = std::min(lo, s.scan_angle_deg);
        hi = std::max(hi, s.scan_angle_deg);
    }
    EXPECT_NEAR(lo, -24.555, 1e-3);
    EXPECT_NEAR(hi, 1.960, 1e-3);
}

TEST(SpinningPattern, vlp32c_pairs_fire_together_with_manual_azimuth_offsets) {
    const auto p = fire(preset("vlp32c"), 0, 32);
    for (int i = 0; i < 32; ++i) {
        EXPECT_EQ(p[i].channel, i);
        EXPECT_EQ(p[i].t_ns, 2304 * (i / 2));
    }
    // Channels 0 and 1 fire at t = 0 with δ = +1.4° and −4.2°.
    EXPECT_NEAR(p[0].azimuth_deg, 1.4, 1e-5);
    EXPECT_NEAR(p[1].azimuth_deg, 360.0 - 4.2, 1e-4);
    EXPECT_NEAR(p[0].scan_angle_deg, -25.0, 1e-6);
    EXPECT_NEAR(p[29].scan_angle_deg, 15.0, 1e-6);
}

TEST(SpinningPattern, ouster_columns_fire_together_at_360_m_over_w_plus_beam_azimuth) {
    const auto m = preset("os1-64-1024x10");
    EXPECT_EQ(m.scan->group_size(), 64u);
    const auto col1 = fire(m, 64, 64);
    const auto col2 = fire(m, 128, 64);
    for (int r = 0; r < 64; ++r) {
        EXPECT_EQ(col1[r].t_ns, 97'656);   // 1/(1024·10) s = 97 656.25 ns
        EXPECT_EQ(col2[r].t_ns, 195'313);  // 195 312.5 ns, rounded
        EXPECT_EQ(col1[r].channel, r);
    }
    const double beam_az[4] = {3.164, 1.055, -1.055, -3.164};
    const auto col256 = fire(m, 256 * 64, 64);
    for (int r = 0; r < 64; ++r) EXPECT_NEAR(col256[r].azimuth_deg, 90.0 + beam_az[r % 4], 1e-4);
    EXPECT_NEAR(col256[0].scan_angle_deg, 16.611, 1e-5);
    EXPECT_NEAR(col256[63].scan_angle_deg, -16.611, 1e-5);
    // One revolution later the azimuth repeats exactly (360/1024 is exact in binary).
    const auto next_rev = fire(m, (256 + 1024) * 64, 1)[0];
    EXPECT_EQ(next_rev.azimuth_deg, col256[0].azimuth_deg);
    EXPECT_EQ(next_rev.t_ns, 125'000'000);  // 1.25 rev at 10 Hz

    const auto os128 = fire(preset("os1-128-1024x20"), 0, 128);
    EXPECT_NEAR(os128[0].scan_angle_deg, 21.4764, 1e-5);
    EXPECT_NEAR(os128[0].azimuth_deg, 4.2521, 1e-5);
    EXPECT_NEAR(os128[127].scan_angle_deg, -21.4764, 1e-5);
}

TEST(SpinningPattern, calibration_tables_have_no_missing_entries) {
    // A short initializer list would leave zeros at the end of a table.
    const auto hdl = fire(preset("hdl64e-s3"), 0, 64);
    for (const auto& p : hdl) EXPECT_NE(p.scan_angle_deg, 0.0f) << p.channel;
    const auto os = fire(preset("os1-128-1024x10"), 0, 128);
    for (const auto& p : os) {
        const double beam_az = std::remainder(double(p.azimuth_deg), 360.0);
        EXPECT_GT(std::abs(beam_az), 1.4) << p.channel;
        EXPECT_GT(std::abs(p.scan_angle_deg), 0.17f) << p.channel;
    }
    EXPECT_NEAR(os[64].scan_angle_deg, -0.1779, 1e-5);
}

TEST(SpinningPattern, firing_offsets_are_sorted_and_shifted_to_zero) {
    SpinningConfig c;
    c.sequence_period_ns = 10'000;
    c.rotation_hz = 10;
    c.lasers = {{5, 0, 3000}, {-5, 0, 1000}, {0, 0, 1000}};
    const SpinningPattern s(c);
    std::vector<PulseSpec> p(6);
    s.pulses(0, 6, p.data());
    EXPECT_EQ(p[0].channel, 1);  // earliest, lower index first on ties
    EXPECT_EQ(p[1].channel, 2);
    EXPECT_EQ(p[2].channel, 0);
    EXPECT_EQ(p[0].t_ns, 0);
    EXPECT_EQ(p[1].t_ns, 0);
    EXPECT_EQ(p[2].t_ns, 2000);
    EXPECT_EQ(p[5].t_ns, 12'000);
    EXPECT_DOUBLE_EQ(s.pulse_rate_hz(), 300'000.0);
}

TEST(SpinningPattern, rejects_bad_configurations) {
    SpinningConfig c;
    c.sequence_period_ns = 10'000;
    EXPECT_THROW(SpinningPattern{c}, ConfigError);  // no lasers
    c.lasers = {{0, 0, 10'000}};
    EXPECT_THROW(SpinningPattern{c}, ConfigError);  // offset = period
    c.lasers = {{95, 0, 0}};
    EXPECT_THROW(SpinningPattern{c}, ConfigError);  // elevation
    c.lasers = {{0, 0, 0}};
    c.rotation_hz = 0;
    EXPECT_THROW(SpinningPattern{c}, ConfigError);
}

}  // namespace
}  // namespace mirage::sensor
