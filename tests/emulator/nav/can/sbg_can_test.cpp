// SPDX-License-Identifier: Apache-2.0
#include "mirage/navcan/sbg_can.hpp"

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

std::vector<nav::NavSample> decode(navcan::SbgCanDecoder& dec,
                                   const std::vector<nav::CanFrame>& frames, bool flush = false) {
    std::vector<nav::NavSample> out;
    auto sink = [&](const nav::NavSample& s) { out.push_back(s); };
    for (const auto& f : frames) dec.feed(f, sink);
    if (flush) dec.flush(sink);
    return out;
}

// UTC 2024-01-01T00:00:00 = GPS 00:00:18, Monday: GPS_TOW = 86 418 000 ms; device clock 1 s.
const std::vector<nav::CanFrame> kUtc = {cf("110#40420F0050A22605"), cf("111#1801010000000000")};

}  // namespace

TEST(SbgCan, device_time_maps_to_gps_through_utc0_and_msl_plus_undulation_is_ellipsoidal) {
    navcan::SbgCanDecoder dec;
    std::vector<nav::CanFrame> frames = kUtc;
    frames.push_back(cf("130#D0121300"));          // EKF_INFO at device 1.25 s
    frames.push_back(cf("132#000000002FF9"));      // roll 0, pitch 0, yaw −0.1745 rad
    frames.push_back(cf("134#081EAE1C184FDD06"));  // 48.1173°, 11.5167°
    frames.push_back(cf("135#A08601001C25"));      // ALTITUDE 100.000 m MSL, UNDULATION 47.5 m
    frames.push_back(cf("137#E8033200FEFF"));      // N 10, E 0.5, D −0.02 m/s
    const auto out = decode(dec, frames);
    ASSERT_EQ(out.size(), 1u);
    const auto& s = out[0];
    EXPECT_EQ(s.source, nav::Protocol::SbgCan);
    EXPECT_EQ(s.t, core::parse_time("2024-01-01T00:00:00Z") + core::Nanos{250'000'000});
    EXPECT_TRUE(s.has(nav::NavSample::kTime | nav::NavSample::kAttitude |
                      nav::NavSample::kPosition | nav::NavSample::kVelocity));
    EXPECT_FALSE(s.has(nav::NavSample::kHeightIsMsl));
    EXPECT_NEAR(s.height_m, 147.5, 1e-9);
    EXPECT_NEAR(s.heading_rad, 2 * std::numbers::pi - 0.1745, 1e-12);  // yaw −10° -> 350°
    EXPECT_NEAR(s.lat_deg, 48.1173, 1e-9);
    EXPECT_NEAR(s.velocity_ned_mps.z(), -0.02, 1e-12);
    EXPECT_EQ(dec.counters().messages_ok, 7u);
}

TEST(SbgCan, encoder_round_trips_and_writes_yaw_in_plus_minus_pi) {
    navcan::SbgCanEncoderConfig cfg;
    cfg.boot = core::parse_time("2024-06-30T23:00:00Z");
    cfg.undulation_m = 47.5;
    nav::NavSample s;
    s.fields = nav::NavSample::kTime | nav::NavSample::kAttitude | nav::NavSample::kPosition |
               nav::NavSample::kVelocity;
    s.t = core::parse_time("2024-07-01T00:00:00.123456Z");
    s.lat_deg = -33.8688;
    s.lon_deg = 151.2093;
    s.height_m = 60.25;
    s.velocity_ned_mps = {-3.5, 12.25, 0.75};
    s.roll_rad = 2.0 * kDeg;
    s.pitch_rad = -3.0 * kDeg;
    s.heading_rad = 350.0 * kDeg;
    std::vector<nav::CanFrame> frames = navcan::sbg_can_encode_utc(s.t, cfg);
    ASSERT_EQ(frames.size(), 2u);
    const auto ekf = navcan::sbg_can_encode(s, cfg);
    frames.insert(frames.end(), ekf.begin(), ekf.end());
    // STATUS_03, EKF_INFO, QUAT, EULER, POS, ALTITUDE, VEL_NED.
    ASSERT_EQ(ekf.size(), 7u);
    EXPECT_EQ(hex_of(ekf[3]), "132#5D01F4FD2FF9");  // 349, −524, −1745 (350° = −10°)
    navcan::SbgCanDecoder dec;
    const auto out = decode(dec, frames);
    ASSERT_EQ(out.size(), 1u);
    const auto& d = out[0];
    EXPECT_EQ(d.t, s.t);  // µs-aligned time survives device clock + ms TOW mapping exactly
    EXPECT_EQ(d.quality, nav::FixQuality::Autonomous);
    EXPECT_NEAR(d.heading_rad, 350.0 * kDeg, 5e-5);
    EXPECT_NEAR(d.roll_rad, 2.0 * kDeg, 5e-5);
    EXPECT_NEAR(d.pitch_rad, -3.0 * kDeg, 5e-5);
    EXPECT_NEAR(d.lat_deg, s.lat_deg, 5e-8);
    EXPECT_NEAR(d.lon_deg, s.lon_deg, 5e-8);
    EXPECT_NEAR(d.height_m, s.height_m, 5e-4);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(d.velocity_ned_mps[i], s.velocity_ned_mps[i], 5e-3);
}

TEST(SbgCan, quaternion_gives_the_attitude_when_euler_is_off) {
    navcan::SbgCanEncoderConfig cfg;
    cfg.ids.ekf_euler = 0;
    nav::NavSample s;
    s.fields = nav::NavSample::kTime | nav::NavSample::kAttitude;
    s.t = core::parse_time("2024-03-01T12:00:00Z");
    cfg.boot = s.t - core::Nanos{3'600'000'000'000};
    s.roll_rad = -20.0 * kDeg;
    s.pitch_rad = 10.0 * kDeg;
    s.heading_rad = 200.0 * kDeg;
    auto frames = navcan::sbg_can_encode_utc(s.t, cfg);
    auto ekf = navcan::sbg_can_encode(s, cfg);
    frames.insert(frames.end(), ekf.begin(), ekf.end());
    navcan::SbgCanDecoder dec;
    const auto out = decode(dec, frames, true);  // no POS/VEL: closes at flush
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].fields, nav::NavSample::kTime | nav::NavSample::kAttitude);
    EXPECT_NEAR(out[0].roll_rad, -20.0 * kDeg, 2e-4);
    EXPECT_NEAR(out[0].pitch_rad, 10.0 * kDeg, 2e-4);
    EXPECT_NEAR(out[0].heading_rad, 200.0 * kDeg, 2e-4);
}

TEST(SbgCan, groups_by_ekf_info_timestamp_and_needs_a_time_mapping) {
    navcan::SbgCanDecoder dec;
    // Before any UTC: an orphan frame, then a group that has no time.
    auto out = decode(dec, {cf("132#000000002FF9"), cf("130#00000000"), cf("132#000000002FF9"),
                            cf("130#00000000")});
    EXPECT_EQ(dec.orphan_frames(), 1u);
    EXPECT_EQ(out.size(), 0u);
    out = decode(dec, kUtc);
    EXPECT_EQ(out.size(), 0u);
    EXPECT_EQ(dec.no_time_groups(), 0u);  // the repeated EKF_INFO(0) kept the group open
    // A new EKF_INFO closes the open partial group: it has a time now (device 0 = −1 s).
    out = decode(dec, {cf("130#40420F00"), cf("137#E8033200FEFF"), cf("130#80841E00")});
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].t, core::parse_time("2023-12-31T23:59:59Z"));
    EXPECT_EQ(out[0].fields, nav::NavSample::kTime | nav::NavSample::kAttitude);
    EXPECT_EQ(out[1].t, core::parse_time("2024-01-01T00:00:00Z"));
    EXPECT_EQ(out[1].fields, nav::NavSample::kTime | nav::NavSample::kVelocity);
}

TEST(SbgCan, device_clock_wrap_and_week_from_previous_mapping) {
    navcan::SbgCanDecoder dec;
    // UTC_0 at device 0xFFFFFF00 µs, TOW 604 799 999 ms (last ms of week 2294), date of it.
    decode(dec, {cf("110#00FFFFFFFF830C24"),
                 cf("111#170C1E173B290627")});  // 2023-12-30 23:59:41.999 UTC
    const auto t0 = dec.gps_time_of(0xFFFFFF00u);
    ASSERT_TRUE(t0.has_value());
    EXPECT_EQ(*t0, core::from_week_time(2294, 604'799'999LL * 1'000'000));
    // 512 µs later the 32-bit clock has wrapped; the week rolls over to 2295.
    EXPECT_EQ(*dec.gps_time_of(0x100u), *t0 + core::Nanos{512'000});
    // A later UTC_0 alone (TOW 1000 ms at device +1.065728 s) gets its week from the mapping.
    decode(dec, {cf("110#00421000E8030000")});
    EXPECT_EQ(*dec.gps_time_of(0x00104200u), core::from_week_time(2295, 1'000'000'000));
}

TEST(SbgCan, status_clears_invalid_fields_and_bad_frames_are_counted) {
    navcan::SbgCanDecoder dec;
    std::vector<nav::CanFrame> frames = kUtc;
    frames.push_back(cf("102#140000000000"));  // mode 4, attitude valid, heading/pos/vel not
    frames.push_back(cf("130#D0121300"));
    frames.push_back(cf("132#0000000030F9"));      // fine but heading invalid per status
    frames.push_back(cf("132#0000000000000"));     // not hex pairs -> cf gives an empty frame
    frames.push_back(cf("132#00000000"));          // DLC 4: truncated
    frames.push_back(cf("132#FF7F00000000"));      // roll 3.2767 rad > π: invalid
    frames.push_back(cf("134#0000000000000080"));  // longitude −214.7°: invalid
    frames.push_back(cf("131#0000000000000000"));  // zero quaternion: invalid
    frames.push_back(cf("111#180D010000000000"));  // month 13: invalid
    frames.push_back(cf("137#E8033200FEFF"));
    frames.push_back(cf("134#081EAE1C184FDD06"));
    frames.push_back(cf("135#A08601001C25"));
    const auto out = decode(dec, frames);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].fields, nav::NavSample::kTime);  // every field flagged invalid by status
    EXPECT_EQ(out[0].quality, nav::FixQuality::DeadReckoning);
    EXPECT_EQ(dec.counters().truncated, 1u);
    EXPECT_EQ(dec.counters().invalid_field, 4u);
    EXPECT_EQ(dec.counters().unsupported, 1u);  // the empty frame with id 0
}
