// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "mirage/core/pose.hpp"
#include "mirage/navpose/pose_buffer.hpp"

using namespace mirage;
using namespace std::chrono_literals;
using navpose::AddStatus;
using navpose::PoseBuffer;
using navpose::PoseStatus;

namespace {
core::GpsTime T(std::int64_t ms) { return core::GpsTime(core::Nanos(ms * 1'000'000)); }
Eigen::Quaterniond yaw(double rad) { return core::quaternion_from_rpy(0, 0, rad); }
}  // namespace

TEST(PoseBuffer, is_empty_then_interpolates_linear_motion_exactly) {
    PoseBuffer b;
    EXPECT_EQ(b.at(T(0)).status, PoseStatus::Empty);
    for (int i = 0; i <= 10; ++i) {
        ASSERT_EQ(b.add_position(T(1000 + 100 * i), {10.0 * 0.1 * i, 0, 0}), AddStatus::Accepted);
        ASSERT_EQ(b.add_attitude(T(1000 + 40 * i), yaw(0.1 * i)), AddStatus::Accepted);
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
    b.add_position(T(0), {0, 0, 0});
    b.add_position(T(10), {0.2, 0, 0});  // 20 m/s
    b.add_attitude(T(0), yaw(0.0));
    b.add_attitude(T(10), yaw(0.01));  // 1 rad/s
    auto q = b.at(T(40));
    EXPECT_EQ(q.status, PoseStatus::Extrapolated);
    EXPECT_EQ(q.age, 30ms);
    EXPECT_NEAR(q.pose.position.x(), 0.8, 1e-12);
    EXPECT_NEAR(core::rpy_from_quaternion(q.pose.attitude).z(), 0.04, 1e-12);
    EXPECT_EQ(b.at(T(60)).status, PoseStatus::Extrapolated);
    EXPECT_EQ(b.at(T(61)).status, PoseStatus::Stale);
    // Messages return: emission resumes.
    b.add_position(T(100), {2.0, 0, 0});
    b.add_attitude(T(100), yaw(0.1));
    EXPECT_EQ(b.at(T(100)).status, PoseStatus::Interpolated);
}

TEST(PoseBuffer, uses_a_reported_velocity_for_extrapolation) {
    PoseBuffer b;
    b.add_position(T(0), {0, 0, 0}, Eigen::Vector3d(0, 5, 0));
    b.add_attitude(T(0), yaw(0));
    EXPECT_NEAR(b.at(T(20)).pose.position.y(), 0.1, 1e-12);
}

TEST(PoseBuffer, rejects_and_counts_bad_samples_without_applying_them) {
    PoseBuffer b;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(b.add_position(T(0), {nan, 0, 0}), AddStatus::NotFinite);
    EXPECT_EQ(b.add_attitude(T(0), Eigen::Quaterniond(nan, 0, 0, 0)), AddStatus::NotFinite);
    EXPECT_EQ(b.add_position(T(0), {0, 0, 0}), AddStatus::Accepted);
    EXPECT_EQ(b.add_position(T(10), {0.1, 0, 0}), AddStatus::Accepted);
    EXPECT_EQ(b.add_position(T(10), {0.2, 0, 0}), AddStatus::Duplicate);  // not counted
    EXPECT_EQ(b.add_position(T(5), {0.2, 0, 0}), AddStatus::TimeBackwards);
    EXPECT_EQ(b.add_position(T(4), {0.2, 0, 0}), AddStatus::TimeBackwards);
    EXPECT_EQ(b.add_position(T(20), {500, 0, 0}), AddStatus::PositionJump);
    b.add_attitude(T(20), yaw(0));
    EXPECT_NEAR(b.at(T(20)).pose.position.x(), 0.2, 1e-12);  // the jump was not applied
    const auto c = b.counters();
    EXPECT_EQ(c.not_finite, 2u);
    EXPECT_EQ(c.time_backwards, 2u);
    EXPECT_EQ(c.duplicates, 1u);
    EXPECT_EQ(c.position_jumps, 1u);
    EXPECT_EQ(c.accepted, 3u);
}

TEST(PoseBuffer, a_persistent_offset_is_taken_as_a_reinitialisation) {
    PoseBuffer b;
    b.add_position(T(0), {0, 0, 0});
    int jumps = 0;
    for (int i = 1; i <= 20; ++i)
        if (b.add_position(T(10 * i), {1000, 0, 0}) == AddStatus::PositionJump) ++jumps;
    // Nine are rejected; the tenth in a row restarts the track there (still counted).
    EXPECT_EQ(jumps, 9);
    EXPECT_EQ(b.counters().position_jumps, 10u);
    b.add_attitude(T(200), yaw(0));
    EXPECT_NEAR(b.at(T(200)).pose.position.x(), 1000, 1e-12);
}

TEST(PoseBuffer, window_gives_a_trajectory_or_nothing_when_stale) {
    PoseBuffer b;
    for (int i = 0; i <= 10; ++i) {
        b.add_position(T(10 * i), {0.1 * i, 0, 0});
        b.add_attitude(T(10 * i), yaw(0));
    }
    const auto w = b.window(T(20), T(120), 10ms);
    ASSERT_TRUE(w.has_value());
    EXPECT_EQ(w->samples().size(), 11u);
    EXPECT_NEAR(w->at(T(55)).position.x(), 0.55, 1e-12);
    EXPECT_NEAR(w->at(T(120)).position.x(), 1.2, 1e-12);  // extrapolated 20 ms
    EXPECT_FALSE(b.window(T(20), T(151), 10ms).has_value());
}
