// SPDX-License-Identifier: Apache-2.0
#include "mirage/navpose/pose_buffer.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "mirage/core/pose.hpp"
#include "navpose_test_util.hpp"

using namespace mirage;
using namespace std::chrono_literals;
using navpose::PoseBuffer;
using navpose::PoseStatus;
using navpose::Track;

namespace {
using navpose::test::T;
using navpose::test::yaw;

navpose::PositionUpdate P(std::int64_t ms, const Eigen::Vector3d& p, std::uint64_t seq = 0,
                          std::optional<Eigen::Vector3d> v = std::nullopt) {
    navpose::PositionUpdate u;
    u.t = T(ms);
    u.local = p;
    u.velocity = v;
    u.tag = {seq, 0};
    return u;
}
navpose::AttitudeUpdate A(std::int64_t ms, double yaw_rad, std::uint64_t seq = 0) {
    navpose::AttitudeUpdate u;
    u.t = T(ms);
    u.attitude = yaw(yaw_rad);
    u.tag = {seq, 0};
    return u;
}

// The sequence numbers a window used on one track, sorted.
std::vector<std::uint64_t> used_on(const navpose::PoseWindow& w, Track track) {
    std::vector<std::uint64_t> out;
    for (const auto& u : w.used)
        if (u.track == track) out.push_back(u.tag.seq);
    std::sort(out.begin(), out.end());
    return out;
}
}  // namespace

TEST(PoseBuffer, is_empty_then_interpolates_linear_motion_exactly) {
    PoseBuffer b;
    EXPECT_EQ(b.at(T(0)).status, PoseStatus::Empty);
    for (int i = 0; i <= 10; ++i) {
        b.add(P(1000 + 100 * i, {10.0 * 0.1 * i, 0, 0}));
        b.add(A(1000 + 40 * i, 0.1 * i));
    }
    // Attitude stops at t = 1400 ms; position runs to 2000 ms: t = 1250 is inside both.
    const auto q = b.at(T(1250));
    EXPECT_EQ(q.status, PoseStatus::Interpolated);
    EXPECT_NEAR(q.pose.position.x(), 2.5, 1e-12);
    EXPECT_NEAR(core::rpy_from_quaternion(q.pose.attitude).z(), 0.625, 1e-12);
    EXPECT_EQ(b.at(T(999)).status, PoseStatus::Stale);  // before the first sample
}

TEST(PoseBuffer, extrapolates_within_the_horizon_then_goes_stale) {
    PoseBuffer b;  // 50 ms horizon
    b.add(P(0, {0, 0, 0}));
    b.add(P(10, {0.2, 0, 0}));  // 20 m/s
    b.add(A(0, 0.0));
    b.add(A(10, 0.01));  // 1 rad/s
    auto q = b.at(T(40));
    EXPECT_EQ(q.status, PoseStatus::Extrapolated);
    EXPECT_EQ(q.age, 30ms);
    EXPECT_NEAR(q.pose.position.x(), 0.8, 1e-12);
    EXPECT_NEAR(core::rpy_from_quaternion(q.pose.attitude).z(), 0.04, 1e-12);
    EXPECT_EQ(b.at(T(60)).status, PoseStatus::Extrapolated);
    EXPECT_EQ(b.at(T(61)).status, PoseStatus::Stale);
    // Messages return: emission resumes.
    b.add(P(100, {2.0, 0, 0}));
    b.add(A(100, 0.1));
    EXPECT_EQ(b.at(T(100)).status, PoseStatus::Interpolated);
}

TEST(PoseBuffer, uses_a_reported_velocity_for_extrapolation) {
    PoseBuffer b;
    b.add(P(0, {0, 0, 0}, 0, Eigen::Vector3d(0, 5, 0)));
    b.add(A(0, 0));
    EXPECT_NEAR(b.at(T(20)).pose.position.y(), 0.1, 1e-12);
}

TEST(PoseBuffer, a_restart_drops_the_old_track_and_stale_updates_are_ignored) {
    PoseBuffer b;
    b.add(P(0, {0, 0, 0}));
    b.add(P(10, {0.1, 0, 0}));
    b.add(P(5, {9, 9, 9}));  // not newer than the track: ignored (the mapper counts such)
    b.add(A(0, 0));
    b.add(A(20, 0));
    EXPECT_NEAR(b.at(T(10)).pose.position.x(), 0.1, 1e-12);
    navpose::PositionUpdate r = P(20, {1000, 0, 0});
    r.restart = true;  // a re-initialisation: nothing interpolates across it
    b.add(r);
    EXPECT_EQ(b.at(T(15)).status, PoseStatus::Stale);
    EXPECT_NEAR(b.at(T(20)).pose.position.x(), 1000, 1e-12);
}

TEST(PoseBuffer, window_gives_a_trajectory_or_nothing_when_stale) {
    PoseBuffer b;
    for (int i = 0; i <= 10; ++i) {
        b.add(P(10 * i, {0.1 * i, 0, 0}));
        b.add(A(10 * i, 0));
    }
    const auto w = b.window(T(20), T(120), 10ms);
    ASSERT_TRUE(w.has_value());
    EXPECT_EQ(w->trajectory.samples().size(), 11u);
    EXPECT_NEAR(w->trajectory.at(T(55)).position.x(), 0.55, 1e-12);
    EXPECT_NEAR(w->trajectory.at(T(120)).position.x(), 1.2, 1e-12);  // extrapolated 20 ms
    EXPECT_FALSE(b.window(T(20), T(151), 10ms).has_value());
}

TEST(PoseBuffer, window_names_the_messages_its_poses_came_from) {
    // Positions from messages 1, 3, 5 at 0/10/20 ms; attitudes from 2, 4, 6 at 0/10/20 ms.
    PoseBuffer b;
    for (int i = 0; i < 3; ++i) {
        b.add(P(10 * i, {0.1 * i, 0, 0}, std::uint64_t(2 * i + 1)));
        b.add(A(10 * i, 0.01 * i, std::uint64_t(2 * i + 2)));
    }
    // Inside (0, 10) ms: interpolation uses both bracketing samples of each track.
    auto w = b.window(T(2), T(8), 3ms);
    ASSERT_TRUE(w);
    EXPECT_EQ(used_on(*w, Track::Position), (std::vector<std::uint64_t>{1, 3}));
    EXPECT_EQ(used_on(*w, Track::Attitude), (std::vector<std::uint64_t>{2, 4}));
    // Exactly on a sample and up to the next one: [10, 15] uses 3 and 5 (4 and 6).
    w = b.window(T(10), T(15), 5ms);
    ASSERT_TRUE(w);
    EXPECT_EQ(used_on(*w, Track::Position), (std::vector<std::uint64_t>{3, 5}));
    // Beyond the newest: extrapolation uses the newest only.
    w = b.window(T(21), T(30), 4ms);
    ASSERT_TRUE(w);
    EXPECT_EQ(used_on(*w, Track::Position), (std::vector<std::uint64_t>{5}));
    EXPECT_EQ(used_on(*w, Track::Attitude), (std::vector<std::uint64_t>{6}));
    EXPECT_EQ(w->used.size(), 2u);  // each message once, though all three knots used it
}
