// SPDX-License-Identifier: Apache-2.0
// NovAtel units and conventions -> NavSample, each with a closed-form case.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "frames.hpp"
#include "mirage/core/time.hpp"
#include "mirage/novatel/convert.hpp"

namespace {

using namespace mirage::novatel;
using namespace mirage::novatel::test;
using mirage::nav::FixQuality;
using mirage::nav::NavSample;

constexpr double kDeg = std::numbers::pi / 180.0;

std::int64_t ns_of(const NavSample& s) { return s.t.time_since_epoch().count(); }

TEST(NovatelConvention, azimuth_350_and_minus_10_both_give_heading_350_degrees) {
    for (double az : {350.0, -10.0}) {
        InsPvaX m = good_inspvax();
        m.azimuth_deg = az;
        const auto out = decode(frame(m));
        ASSERT_EQ(out.size(), 1U) << az;
        EXPECT_NEAR(out[0].heading_rad, 350.0 * kDeg, 1e-12) << az;
    }
    InsPvaS m = good_inspvas();
    m.azimuth_deg = 90.0;  // clockwise from north: east
    const auto out = decode(frame(m));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_NEAR(out[0].heading_rad, std::numbers::pi / 2, 1e-12);
}

TEST(NovatelConvention, up_velocity_becomes_negative_down) {
    InsPvaX m = good_inspvax();
    m.vel_north_mps = 3.0;
    m.vel_east_mps = -4.0;
    m.vel_up_mps = 2.0;
    auto out = decode(frame(m));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].velocity_ned_mps, Eigen::Vector3d(3.0, -4.0, -2.0));
    InsPvaS s = good_inspvas();
    s.vel_up_mps = -1.5;  // descending
    out = decode(frame(s));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].velocity_ned_mps.z(), 1.5);
}

TEST(NovatelConvention, msl_plus_undulation_is_ellipsoidal_but_inspvas_is_taken_as_is) {
    InsPvaX x = good_inspvax();
    x.height_msl_m = 100.0;
    x.undulation_m = 47.5F;
    auto out = decode(frame(x));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].height_m, 147.5);
    EXPECT_FALSE(out[0].has(NavSample::kHeightIsMsl));

    BestPos b;
    b.position_type = kPosNarrowInt;
    b.lat_deg = 10.0;
    b.height_msl_m = 100.0;
    b.undulation_m = -17.0F;
    out = decode(frame(b));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].height_m, 83.0);
    EXPECT_EQ(out[0].quality, FixQuality::RtkFixed);

    InsPvaS s = good_inspvas();
    s.height_m = 100.0;
    out = decode(frame(s));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].height_m, 100.0);
}

// NovAtel INSPVA: vehicle frame X right, Y forward, Z up; roll right-handed about Y, pitch
// right-handed about X, azimuth left-handed about Z (clockwise from north), applied
// azimuth -> pitch -> roll from local level ENU.
Eigen::Matrix3d novatel_R_enu_rfu(double roll_deg, double pitch_deg, double az_deg) {
    using Eigen::AngleAxisd;
    using Eigen::Vector3d;
    return (AngleAxisd(-az_deg * kDeg, Vector3d::UnitZ()) *
            AngleAxisd(pitch_deg * kDeg, Vector3d::UnitX()) *
            AngleAxisd(roll_deg * kDeg, Vector3d::UnitY()))
        .toRotationMatrix();
}

// NavSample convention: R_ned_frd = Rz(heading)·Ry(pitch)·Rx(roll).
Eigen::Matrix3d aerospace_R_ned_frd(const NavSample& s) {
    using Eigen::AngleAxisd;
    using Eigen::Vector3d;
    return (AngleAxisd(s.heading_rad, Vector3d::UnitZ()) *
            AngleAxisd(s.pitch_rad, Vector3d::UnitY()) * AngleAxisd(s.roll_rad, Vector3d::UnitX()))
        .toRotationMatrix();
}

TEST(NovatelConvention, roll_pitch_azimuth_give_the_same_body_axes_as_ned_euler_angles) {
    // ENU -> NED and RFU -> FRD are the same axis swap (x<->y, z negated).
    Eigen::Matrix3d swap;
    swap << 0, 1, 0, 1, 0, 0, 0, 0, -1;
    const double cases[][3] = {{0, 0, 0},      {10, 0, 0},     {0, 5, 0},      {0, 0, 30},
                               {-20, 15, 200}, {45, -30, 359}, {170, 80, 123}, {-3, -2, 1}};
    for (const auto& c : cases) {
        InsPvaS m = good_inspvas();
        m.roll_deg = c[0];
        m.pitch_deg = c[1];
        m.azimuth_deg = c[2];
        const auto out = decode(frame(m));
        ASSERT_EQ(out.size(), 1U);
        const Eigen::Matrix3d expected = swap * novatel_R_enu_rfu(c[0], c[1], c[2]) * swap;
        EXPECT_TRUE(aerospace_R_ned_frd(out[0]).isApprox(expected, 1e-12))
            << c[0] << " " << c[1] << " " << c[2];
    }
}

TEST(NovatelConvention, positive_roll_is_right_side_down_and_positive_pitch_is_nose_up) {
    InsPvaS m = good_inspvas();
    m.roll_deg = 10.0;
    auto out = decode(frame(m));
    ASSERT_EQ(out.size(), 1U);
    // Body right axis (FRD y) in NED: its down component is +sin(10°).
    Eigen::Vector3d right = aerospace_R_ned_frd(out[0]) * Eigen::Vector3d::UnitY();
    EXPECT_NEAR(right.z(), std::sin(10.0 * kDeg), 1e-12);
    EXPECT_NEAR(out[0].roll_rad, 10.0 * kDeg, 1e-15);

    m.roll_deg = 0.0;
    m.pitch_deg = 5.0;
    out = decode(frame(m));
    ASSERT_EQ(out.size(), 1U);
    // Body forward axis points up: down component −sin(5°).
    Eigen::Vector3d fwd = aerospace_R_ned_frd(out[0]) * Eigen::Vector3d::UnitX();
    EXPECT_NEAR(fwd.z(), -std::sin(5.0 * kDeg), 1e-12);
    EXPECT_NEAR(out[0].pitch_rad, 5.0 * kDeg, 1e-15);
}

TEST(NovatelConvention, header_week_and_ms_are_gps_time_without_leap_seconds) {
    InsPvaX m = good_inspvax();
    auto out = decode(frame(m, 2163, 329'807'000));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_TRUE(out[0].has(NavSample::kTime));
    EXPECT_EQ(ns_of(out[0]), (2163LL * 604'800 + 329'807) * 1'000'000'000LL);
}

TEST(NovatelConvention, time_is_continuous_across_week_ends_and_the_1024_week_rollover) {
    for (int w : {1023, 2047, 2400}) {
        const auto week = static_cast<std::uint16_t>(w);
        const auto a = decode(frame(good_inspvax(), week, 604'799'999));
        const auto b = decode(frame(good_inspvax(), static_cast<std::uint16_t>(week + 1), 0));
        ASSERT_EQ(a.size(), 1U);
        ASSERT_EQ(b.size(), 1U);
        EXPECT_EQ(ns_of(b[0]) - ns_of(a[0]), 1'000'000) << week;
        EXPECT_EQ(mirage::core::to_week_time(b[0].t).week, week + 1);
    }
    // INSPVAS: body week + f64 seconds.
    InsPvaS s1 = good_inspvas();
    s1.week = 1023;
    s1.seconds_of_week = 604'799.999;
    InsPvaS s2 = good_inspvas();
    s2.week = 1024;
    s2.seconds_of_week = 0.0;
    const auto a = decode(frame(s1));
    const auto b = decode(frame(s2));
    ASSERT_EQ(a.size(), 1U);
    ASSERT_EQ(b.size(), 1U);
    EXPECT_EQ(ns_of(b[0]) - ns_of(a[0]), 1'000'000);
    EXPECT_EQ(ns_of(b[0]), 1024LL * 604'800 * 1'000'000'000LL);
}

TEST(NovatelConvention, unknown_time_status_gives_no_time_field) {
    LongHeader h = header_at(kInsPvaXId, 2300, 1000);
    h.time_status = kTimeUnknown;
    const auto out = decode(frame_long(h, pack(good_inspvax())));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_FALSE(out[0].has(NavSample::kTime));
    EXPECT_TRUE(out[0].has(NavSample::kPosition | NavSample::kAttitude));
}

TEST(NovatelConvention, position_types_and_ins_status_map_to_fix_quality) {
    EXPECT_EQ(quality_from_position_type(kPosNone), FixQuality::None);
    EXPECT_EQ(quality_from_position_type(kPosSingle), FixQuality::Autonomous);
    EXPECT_EQ(quality_from_position_type(kPosPsrDiff), FixQuality::Differential);
    EXPECT_EQ(quality_from_position_type(kPosNarrowInt), FixQuality::RtkFixed);
    EXPECT_EQ(quality_from_position_type(kPosInsRtkFloat), FixQuality::RtkFloat);
    EXPECT_EQ(quality_from_position_type(kPosInsRtkFixed), FixQuality::RtkFixed);
    EXPECT_EQ(quality_from_position_type(kPosInsPpp), FixQuality::Differential);
    EXPECT_EQ(quality_from_position_type(kPosPropagated), FixQuality::DeadReckoning);
    EXPECT_EQ(quality_from_position_type(999), FixQuality::Unknown);
    EXPECT_EQ(quality_from_ins_status(kInsAligning), FixQuality::None);
    EXPECT_EQ(quality_from_ins_status(kInsSolutionGood), FixQuality::Autonomous);
    EXPECT_EQ(quality_from_ins_status(kInsSolutionFree), FixQuality::DeadReckoning);
    for (FixQuality q : {FixQuality::None, FixQuality::Autonomous, FixQuality::Differential,
                         FixQuality::RtkFloat, FixQuality::RtkFixed, FixQuality::DeadReckoning})
        EXPECT_EQ(quality_from_position_type(position_type_for(q)), q);
}

TEST(NovatelConvention, unaligned_ins_and_unsolved_bestpos_give_time_only_with_quality_none) {
    InsPvaX x = good_inspvax();
    x.ins_status = kInsAligning;
    x.lat_deg = std::nan("");  // an unaligned INS may send anything
    auto out = decode(frame(x));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].fields, NavSample::kTime);
    EXPECT_EQ(out[0].quality, FixQuality::None);

    BestPos b;
    b.solution_status = 1;  // INSUFFICIENT_OBS
    b.position_type = kPosSingle;
    out = decode(frame(b));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].fields, NavSample::kTime);
    EXPECT_EQ(out[0].quality, FixQuality::None);
}

TEST(NovatelConvention, inspva_long_header_507_decodes_like_inspvas) {
    InsPvaS m = good_inspvas();
    m.azimuth_deg = 45.0;
    const auto out =
        decode(frame_long(header_at(kInsPvaId, static_cast<std::uint16_t>(m.week), 1000), pack(m)));
    ASSERT_EQ(out.size(), 1U);
    EXPECT_NEAR(out[0].heading_rad, 45.0 * kDeg, 1e-12);
    EXPECT_EQ(out[0].height_m, 500.0);
    EXPECT_EQ(ns_of(out[0]), (2300LL * 604'800 + 1) * 1'000'000'000LL);
}

}  // namespace
