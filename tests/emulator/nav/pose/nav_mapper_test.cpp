// SPDX-License-Identifier: Apache-2.0
// The one mapping from navigation samples to scene-frame track updates and its rejection rules
// (TrackGate): what is refused, how it is counted, heights, convergence, heading-only messages.
#include "mirage/navpose/nav_mapper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "mirage/core/georef.hpp"
#include "navpose_test_util.hpp"
#include "test_units.hpp"

using namespace mirage;
using navpose::AddStatus;
using navpose::NavMapper;
using navpose::TrackGate;
using F = nav::NavSample;

namespace {
using mirage::test::kDeg;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using navpose::test::T;
using navpose::test::yaw;

// UTM 32N anchored on the central meridian (9° E) at ~45.1° N.
navpose::NavFrame utm() {
    return navpose::NavFrame::from_georef(
        core::Georef::projected(32632, {500000.0, 5000000.0, 0.0}));
}

F fix(std::int64_t ms, double lat, double lon, double h) {
    F s;
    s.fields = F::kTime | F::kPosition;
    s.t = T(ms);
    s.lat_deg = lat;
    s.lon_deg = lon;
    s.height_m = h;
    return s;
}
F attitude(std::int64_t ms, double roll, double pitch, double heading) {
    F s;
    s.fields = F::kTime | F::kAttitude;
    s.t = T(ms);
    s.roll_rad = roll;
    s.pitch_rad = pitch;
    s.heading_rad = heading;
    return s;
}
F heading_only(std::int64_t ms, double heading) {
    F s;
    s.fields = F::kTime | F::kHeading;
    s.t = T(ms);
    s.heading_rad = heading;
    s.pitch_rad = 0.3;  // PTNL,AVR's tilt: not a flagged field, never used
    return s;
}
}  // namespace

TEST(TrackGate, refuses_bad_track_updates_with_their_reason) {
    TrackGate g;
    EXPECT_EQ(g.position(T(0), {kNaN, 0, 0}, std::nullopt).status, AddStatus::NotFinite);
    EXPECT_EQ(g.attitude(T(0), Eigen::Quaterniond(kNaN, 0, 0, 0)).status, AddStatus::NotFinite);
    const auto first = g.position(T(0), {0, 0, 0}, std::nullopt);
    EXPECT_EQ(first.status, AddStatus::Accepted);
    EXPECT_TRUE(first.restart);  // the first sample starts the track
    EXPECT_EQ(g.position(T(10), {0.1, 0, 0}, std::nullopt).status, AddStatus::Accepted);
    EXPECT_EQ(g.position(T(10), {0.2, 0, 0}, std::nullopt).status, AddStatus::Duplicate);
    EXPECT_EQ(g.position(T(5), {0.2, 0, 0}, std::nullopt).status, AddStatus::TimeBackwards);
    // Predicted at 20 ms: 0.2 m (10 m/s from the last two fixes); 20.3 m off is a jump.
    EXPECT_EQ(g.position(T(20), {20.5, 0, 0}, std::nullopt).status, AddStatus::PositionJump);
    EXPECT_EQ(g.position(T(20), {19.9, 0, 0}, std::nullopt).status, AddStatus::Accepted);
    EXPECT_EQ(g.attitude(T(0), yaw(0)).status, AddStatus::Accepted);
    EXPECT_EQ(g.attitude(T(0), yaw(0)).status, AddStatus::Duplicate);
    EXPECT_EQ(g.attitude(T(-1), yaw(0)).status, AddStatus::TimeBackwards);
}

TEST(TrackGate, ten_jumps_in_a_row_restart_the_track_a_long_silence_too) {
    TrackGate g;
    g.position(T(0), {0, 0, 0}, std::nullopt);
    int jumps = 0;
    for (int i = 1; i <= 9; ++i)
        jumps +=
            g.position(T(10 * i), {1000, 0, 0}, std::nullopt).status == AddStatus::PositionJump;
    EXPECT_EQ(jumps, 9);
    const auto tenth = g.position(T(100), {1000, 0, 0}, std::nullopt);
    EXPECT_EQ(tenth.status, AddStatus::Reinitialised);
    EXPECT_TRUE(tenth.restart);
    EXPECT_EQ(g.position(T(110), {1000.1, 0, 0}, std::nullopt).status, AddStatus::Accepted);
    // 3 s of silence: no prediction to judge by, the far fix starts a new track.
    const auto after = g.position(T(3110), {5000, 0, 0}, std::nullopt);
    EXPECT_EQ(after.status, AddStatus::Accepted);
    EXPECT_TRUE(after.restart);
}

TEST(NavMapper, counts_every_sample_in_one_place_and_refuses_bad_ones_whole) {
    NavMapper m(utm());
    F untimed = fix(0, 45.1, 9.0, 100);
    untimed.fields &= ~F::kTime;
    F time_only;
    time_only.fields = F::kTime | F::kVelocity;  // RMC: time and velocity, no pose
    F nan_vel = fix(0, 45.1, 9.0, 100);
    nan_vel.fields |= F::kVelocity;
    nan_vel.velocity_ned_mps.x() = kNaN;
    EXPECT_FALSE(m.map(untimed).position);
    EXPECT_FALSE(m.map(time_only).position);
    EXPECT_FALSE(m.map(nan_vel).position);  // a NaN anywhere refuses the whole sample
    EXPECT_FALSE(m.map(fix(0, 91.0, 9.0, 100)).position);  // no projection throws on the path
    EXPECT_TRUE(m.map(fix(0, 45.1, 9.0, 100)).position);
    EXPECT_TRUE(m.map(attitude(0, 0, 0, 0)).attitude);
    EXPECT_FALSE(m.map(fix(0, 45.1, 9.0, 100)).position);      // duplicate epoch
    EXPECT_FALSE(m.map(fix(-100, 45.1, 9.0, 100)).position);   // backwards
    EXPECT_FALSE(m.map(fix(100, 45.101, 9.0, 100)).position);  // 111 m north: a jump
    const navpose::NavCounters& c = m.counters();
    EXPECT_EQ(c.samples, 9u);
    EXPECT_EQ(c.no_time, 1u);
    EXPECT_EQ(c.no_pose, 1u);
    EXPECT_EQ(c.not_finite, 2u);
    EXPECT_EQ(c.applied, 2u);
    EXPECT_EQ(c.duplicates, 1u);
    EXPECT_EQ(c.time_backwards, 1u);
    EXPECT_EQ(c.position_jumps, 1u);
    EXPECT_EQ(c.rejected(), 4u);
    EXPECT_EQ(navpose::nav_counters_line({}, c),
              "nav samples 9 applied 2, decode rejected 0 (bad checksum 0, truncated 0, invalid "
              "0), pose rejected 4 (time backwards 1, jumps 1, not finite 2, outside the scene 0), "
              "without time 1, "
              "without pose 1, duplicates 1, re-initialisations 0");
}

TEST(NavMapper, msl_heights_get_the_undulation_and_the_tag_travels_with_the_update) {
    navpose::NavMapperConfig cfg;
    cfg.undulation_m = 47.5;
    NavMapper m(utm(), cfg);
    F s = fix(0, 45.1, 9.0, 100);
    s.fields |= F::kHeightIsMsl;
    const auto u = m.map(s, {7, 1234});
    ASSERT_TRUE(u.position);
    EXPECT_NEAR(u.position->local.z(), 147.5, 1e-9);
    EXPECT_EQ(u.position->tag.seq, 7u);
    EXPECT_EQ(u.position->tag.arrival_ns, 1234);
    EXPECT_TRUE(u.position->restart);
    const auto ellipsoidal = m.map(fix(10, 45.1, 9.0, 140));  // within 20 m of the last
    ASSERT_TRUE(ellipsoidal.position);
    EXPECT_NEAR(ellipsoidal.position->local.z(), 140.0, 1e-9);
}

TEST(NavMapper, attitudes_use_the_convergence_at_the_newest_fix) {
    // 1° east of the central meridian at 45.1° N, grid north is ~0.71° east of true north: a
    // true heading of 90° is a grid bearing of ~89.29°, i.e. ENU yaw ~0.71°.
    // The scene anchored there (a position 79 km from the anchor would be outside the scene).
    NavMapper m(
        navpose::NavFrame::from_georef(core::Georef::projected(32632, {578800.0, 4995000.0, 0.0})));
    ASSERT_TRUE(m.map(fix(0, 45.1, 10.0, 100)).position);
    const auto u = m.map(attitude(0, 0, 0, 90 * kDeg));
    ASSERT_TRUE(u.attitude);
    const double gamma = utm().convergence_rad(45.1, 10.0);
    EXPECT_GT(gamma, 0.7 * kDeg);
    EXPECT_NEAR(core::rpy_from_quaternion(u.attitude->attitude).z(), gamma, 1e-9);
}

TEST(NavMapper, a_heading_alone_takes_the_last_roll_and_pitch_or_level) {
    NavMapper m(utm());
    // Before any attitude: level.
    auto u = m.map(heading_only(0, 30 * kDeg));
    ASSERT_TRUE(u.attitude);
    EXPECT_EQ(u.attitude->ned_rpy, Eigen::Vector3d(0, 0, 30 * kDeg));
    // After a full attitude: its roll and pitch with the new heading.
    ASSERT_TRUE(m.map(attitude(10, 2 * kDeg, -3 * kDeg, 40 * kDeg)).attitude);
    u = m.map(heading_only(20, 50 * kDeg));
    ASSERT_TRUE(u.attitude);
    EXPECT_NEAR(u.attitude->ned_rpy.x(), 2 * kDeg, 1e-15);
    EXPECT_NEAR(u.attitude->ned_rpy.y(), -3 * kDeg, 1e-15);
    EXPECT_NEAR(u.attitude->ned_rpy.z(), 50 * kDeg, 1e-15);
    const Eigen::Quaterniond want = utm().local_attitude(2 * kDeg, -3 * kDeg, 50 * kDeg, 45.1, 9.0);
    EXPECT_LT(u.attitude->attitude.angularDistance(want), 1e-6);
    EXPECT_EQ(m.counters().applied, 3u);
}

// A position 16 384 m or more from the anchor on any axis is another frame than the scene's:
// refused and counted, before the gate sees it (docs/conventions.md §3).
TEST(NavMapper, positions_beyond_the_scene_range_are_refused_as_outside_the_scene) {
    NavMapper m(utm());
    const double lat0 = 45.1535;  // about the anchor (UTM 32N 500000 E, 5000000 N)
    const auto north = m.map(fix(0, lat0 + 0.1, 9.0, 100));  // ~11 km north: inside
    ASSERT_TRUE(north.position);
    EXPECT_NEAR(north.position->local.y(), 11100, 200);
    EXPECT_FALSE(m.map(fix(100, lat0 + 0.2, 9.0, 100)).position);    // ~22 km north
    EXPECT_FALSE(m.map(fix(200, lat0 + 0.1, 9.0, 20000)).position);  // 20 km up
    EXPECT_FALSE(m.map(fix(300, lat0, 9.0 + 0.3, 100)).position);    // ~24 km east
    EXPECT_TRUE(m.map(fix(400, lat0 + 0.1, 9.0, 100.5)).position);   // the track goes on
    const navpose::NavCounters& c = m.counters();
    EXPECT_EQ(c.outside_scene, 3u);
    EXPECT_EQ(c.rejected(), 3u);
    EXPECT_EQ(c.position_jumps, 0u);
    EXPECT_EQ(c.applied, 2u);
}
