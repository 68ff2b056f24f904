// SPDX-License-Identifier: Apache-2.0
#include "mirage/navcan/oxts_can.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "can_test_util.hpp"
#include "test_units.hpp"

using namespace mirage;
using navcan::test::cf;
using navcan::test::hex_of;

namespace {

using mirage::test::kDeg;

// 2023-11-14T22:13:20 GPS (= Unix 1700000000 s as a calendar, read in the GPS scale).
core::GpsTime example_time() {
    return core::GpsTime{
        core::Nanos{(1'700'000'000LL - core::kGpsEpochUnixSeconds) * core::kNsPerSecond}};
}

nav::NavSample example_sample() {
    nav::NavSample s;
    s.fields = nav::NavSample::kTime | nav::NavSample::kPosition | nav::NavSample::kVelocity |
               nav::NavSample::kAttitude | nav::NavSample::kHeightIsMsl;
    s.t = example_time();
    s.lat_deg = 48.1173;
    s.lon_deg = 11.5167;
    s.height_m = 545.4;
    s.velocity_ned_mps = {10.0, 0.5, -0.02};
    s.heading_rad = 84.40 * kDeg;
    s.pitch_rad = 1.20 * kDeg;
    s.roll_rad = -0.50 * kDeg;
    return s;
}

std::vector<nav::NavSample> decode(navcan::OxtsCanDecoder& dec,
                                   const std::vector<nav::CanFrame>& frames) {
    std::vector<nav::NavSample> out;
    for (const auto& f : frames) dec.feed(f, [&](const nav::NavSample& s) { out.push_back(s); });
    return out;
}

}  // namespace

TEST(OxtsCan, encoder_reproduces_the_reference_example_frames) {
    const auto frames = navcan::oxts_can_encode(example_sample());
    std::vector<std::string> hex;
    for (const auto& f : frames) hex.push_back(hex_of(f));
    // §7.1 example frames, plus the time frames: 2023-11-14 22:13:20.00 and ms since GPS epoch.
    ASSERT_EQ(hex.size(), 6u);
    EXPECT_EQ(hex[0], "600#17140B0E00140D16");
    const std::int64_t ms = (1'700'000'000LL - core::kGpsEpochUnixSeconds) * 1000;
    EXPECT_EQ(ms, 1'384'035'200'000LL);
    EXPECT_EQ(hex[1], "630#002CED3E420112");  // 48-bit LE ms, UtcOffset 18
    EXPECT_EQ(hex[2], "601#081EAE1C184FDD06");
    EXPECT_EQ(hex[3], "602#78520800");
    EXPECT_EQ(hex[4], "603#E8033200FEFFE903");
    EXPECT_EQ(hex[5], "607#F8207800CEFF");
}

TEST(OxtsCan, reference_frames_decode_to_the_stated_values) {
    navcan::OxtsCanDecoder dec;
    const std::vector<nav::CanFrame> frames = {cf("630#002CED3E420112"), cf("601#081EAE1C184FDD06"),
                                               cf("602#78520800"), cf("603#E8033200FEFFE903"),
                                               cf("607#F8207800CEFF")};
    const auto out = decode(dec, frames);
    ASSERT_EQ(out.size(), 1u);
    const nav::NavSample& s = out[0];
    EXPECT_EQ(s.source, nav::Protocol::OxtsCan);
    EXPECT_TRUE(s.has(nav::NavSample::kTime | nav::NavSample::kPosition |
                      nav::NavSample::kVelocity | nav::NavSample::kAttitude |
                      nav::NavSample::kHeightIsMsl));
    EXPECT_EQ(s.t, example_time());
    EXPECT_NEAR(s.lat_deg, 48.1173, 1e-9);
    EXPECT_NEAR(s.lon_deg, 11.5167, 1e-9);
    EXPECT_NEAR(s.height_m, 545.4, 1e-9);
    EXPECT_NEAR(s.velocity_ned_mps.x(), 10.0, 1e-12);
    EXPECT_NEAR(s.velocity_ned_mps.y(), 0.5, 1e-12);
    EXPECT_NEAR(s.velocity_ned_mps.z(), -0.02, 1e-12);  // Down stays down: climbing at 2 cm/s
    EXPECT_NEAR(s.heading_rad, 84.40 * kDeg, 1e-12);
    EXPECT_NEAR(s.pitch_rad, 1.20 * kDeg, 1e-12);
    EXPECT_NEAR(s.roll_rad, -0.50 * kDeg, 1e-12);
    EXPECT_EQ(dec.utc_offset_s(), 18);
    EXPECT_EQ(dec.counters().messages_ok, 5u);
    EXPECT_EQ(dec.counters().samples, 1u);
}

TEST(OxtsCan, heading_is_unsigned_so_minus_ten_degrees_is_350) {
    nav::NavSample s = example_sample();
    s.heading_rad = -10.0 * kDeg;  // an encoder input outside [0, 2π) is wrapped
    auto frames = navcan::oxts_can_encode(s);
    EXPECT_EQ(hex_of(frames.back()), "607#B8887800CEFF");  // 35000 = 0x88B8
    navcan::OxtsCanDecoder dec;
    auto out = decode(dec, frames);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(out[0].heading_rad, 350.0 * kDeg, 1e-12);
    // 359.999° rounds to 360.00, which the signal cannot carry: it becomes 0.
    s.heading_rad = 359.999 * kDeg;
    EXPECT_EQ(hex_of(navcan::oxts_can_encode(s).back()), "607#00007800CEFF");
}

TEST(OxtsCan, datetime_alone_gives_gps_time_to_the_hundredth) {
    navcan::OxtsCanDecoder dec;
    // 2024-02-29 23:59:59.99 GPS: a leap day, hundredths 99.
    const auto out = decode(dec, {cf("600#1814021D633B3B17"), cf("607#F8207800CEFF")});
    ASSERT_EQ(out.size(), 0u);  // 0x601..0x603 still expected: the group stays open
    std::vector<nav::NavSample> flushed;
    dec.flush([&](const nav::NavSample& s) { flushed.push_back(s); });
    ASSERT_EQ(flushed.size(), 1u);
    // Days 1980-01-06 .. 2024-02-29 = 16125 (2024-01-01 is day 16066 of GPS, +59).
    const std::int64_t expect_ns =
        (16125LL * 86'400 + 23 * 3600 + 59 * 60 + 59) * core::kNsPerSecond + 990'000'000;
    EXPECT_EQ(flushed[0].t.time_since_epoch().count(), expect_ns);
    EXPECT_EQ(flushed[0].fields, nav::NavSample::kTime | nav::NavSample::kAttitude);
}

TEST(OxtsCan, groups_one_cycle_whatever_the_order_and_splits_on_repeats) {
    navcan::OxtsCanDecoder dec;
    nav::NavSample a = example_sample();
    nav::NavSample b = a;
    b.t += core::Nanos{10'000'000};
    b.lat_deg += 1e-5;
    auto fa = navcan::oxts_can_encode(a);
    auto fb = navcan::oxts_can_encode(b);
    // Cycle A in ID order with 0x630 last (as a unit sending in ID order does), cycle B reversed.
    std::vector<nav::CanFrame> seq = {fa[0], fa[2], fa[3], fa[4], fa[5], fa[1]};
    seq.insert(seq.end(), fb.rbegin(), fb.rend());
    auto out = decode(dec, seq);
    dec.flush([&](const nav::NavSample& s) { out.push_back(s); });
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].t, a.t);
    EXPECT_NEAR(out[0].lat_deg, a.lat_deg, 1e-9);
    EXPECT_EQ(out[1].t, b.t);
    EXPECT_NEAR(out[1].lat_deg, b.lat_deg, 1e-9);
    // A closed at its 0x607 and absorbed its late 0x630; B closed at its 0x630 (first time
    // frame) and absorbed its trailing 0x600: no group was left incomplete.
    EXPECT_EQ(dec.incomplete_groups(), 0u);
    EXPECT_EQ(dec.counters().messages_ok, 12u);
}

TEST(OxtsCan, stamped_frames_far_apart_do_not_share_a_group) {
    navcan::OxtsCanDecoder dec;
    auto f = navcan::oxts_can_encode(example_sample());
    std::vector<nav::NavSample> out;
    auto sink = [&](const nav::NavSample& s) { out.push_back(s); };
    dec.feed(nav::StampedCanFrame{0, f[1]}, sink);           // time
    dec.feed(nav::StampedCanFrame{50'000'000, f[5]}, sink);  // attitude 50 ms later
    dec.flush(sink);
    EXPECT_EQ(out.size(), 0u);
    EXPECT_EQ(dec.incomplete_groups(), 2u);
}

TEST(OxtsCan, bad_frames_are_counted_and_not_applied) {
    navcan::OxtsCanDecoder dec;
    std::vector<nav::CanFrame> frames = {
        cf("630#002CED3E420112"),
        cf("601#081EAE1C184FDD"),    // DLC 7: truncated
        cf("607#A08C7800CEFF"),      // heading 360.00: out of range
        cf("601#00E1F505184FDD06"),  // latitude 10.0° ... valid, applied
        cf("601#FFFFFF7F184FDD06"),  // latitude 214.7°: out of range
        cf("600#17140D0E00140D16"),  // month 13
        cf("602#785208"),            // DLC 3: truncated
        cf("700#00"),                // another ID
        cf("602#78520800"),
        cf("603#E8033200FEFFE903"),
        cf("607#F8207800CEFF")};
    nav::CanFrame rtr = cf("601#R");
    frames.insert(frames.begin() + 2, rtr);
    const auto out = decode(dec, frames);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_NEAR(out[0].lat_deg, 10.0, 1e-12);
    EXPECT_EQ(dec.counters().truncated, 2u);
    EXPECT_EQ(dec.counters().invalid_field, 3u);
    EXPECT_EQ(dec.counters().unsupported, 2u);
    EXPECT_EQ(dec.counters().messages_ok, 5u);
}

TEST(OxtsCan, configured_ids_and_accel_rate_round_trip) {
    navcan::OxtsCanConfig cfg;
    cfg.ids.date_time = 0;
    cfg.ids.milli_time = 0x1A30;
    cfg.ids.lat_lon = 0x1A01;
    cfg.ids.altitude = 0x1A02;
    cfg.ids.velocity = 0x1A03;
    cfg.ids.accel_vehicle = 0x1A05;
    cfg.ids.heading_pitch_roll = 0x1A07;
    cfg.ids.rate_vehicle = 0x1A08;
    cfg.ids.extended = true;
    cfg.altitude_is_ellipsoidal = true;
    nav::NavSample s = example_sample();
    s.fields = (s.fields & ~nav::NavSample::kHeightIsMsl) | nav::NavSample::kAcceleration |
               nav::NavSample::kAngularRate;
    s.t += core::Nanos{123'000'000};
    s.accel_frd_mps2 = {1.23, -0.45, 9.81};
    s.rate_frd_radps = {0.1 * kDeg, -2.5 * kDeg, 30.0 * kDeg};
    const auto frames = navcan::oxts_can_encode(s, cfg.ids);
    ASSERT_EQ(frames.size(), 7u);
    for (const auto& f : frames) EXPECT_TRUE(f.extended);
    navcan::OxtsCanDecoder dec(cfg);
    // The default-ID decoder ignores every one of them.
    navcan::OxtsCanDecoder def;
    EXPECT_EQ(decode(def, frames).size(), 0u);
    EXPECT_EQ(def.counters().unsupported, 7u);
    const auto out = decode(dec, frames);
    ASSERT_EQ(out.size(), 1u);
    const auto& d = out[0];
    EXPECT_EQ(d.t, s.t);
    EXPECT_FALSE(d.has(nav::NavSample::kHeightIsMsl));
    EXPECT_TRUE(d.has(nav::NavSample::kAcceleration | nav::NavSample::kAngularRate));
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(d.accel_frd_mps2[i], s.accel_frd_mps2[i], 0.005);
        EXPECT_NEAR(d.rate_frd_radps[i], s.rate_frd_radps[i], 0.005 * kDeg);
    }
}

TEST(OxtsCan, encoder_saturates_out_of_range_values) {
    nav::NavSample s = example_sample();
    s.velocity_ned_mps = {500.0, -500.0, std::nan("")};
    s.pitch_rad = 100.0 * kDeg;
    const auto frames = navcan::oxts_can_encode(s);
    EXPECT_EQ(hex_of(frames[4]), "603#FF7F00800000FFFF");  // ±327.67/-327.68, NaN -> 0, 655.35
    EXPECT_EQ(hex_of(frames[5]), "607#F8202823CEFF");      // pitch clamps at 90.00°
}
