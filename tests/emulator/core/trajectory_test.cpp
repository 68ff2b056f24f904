// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "mirage/core/error.hpp"
#include "test_units.hpp"

using namespace mirage::core;

namespace {

using mirage::test::kDeg;
using mirage::test::kS;
const GpsTime kT0 = GpsTime{Nanos{1'388'102'418 * kS}};  // 2024-01-01T00:00:00Z

StampedPose sample(GpsTime t, Eigen::Vector3d p, double yaw_deg = 0) {
    return {t, {p, quaternion_from_rpy(0, 0, yaw_deg * kDeg)}};
}

Eigen::Vector3d quadratic(double t) { return {t * t, 0.5 * t * t - 3 * t, 2 * t + 1}; }

}  // namespace

TEST(Trajectory, linear_midpoint_is_exact) {
    const Trajectory tr({sample(kT0, {0, 0, 0}), sample(kT0 + Nanos{2 * kS}, {2, 4, 6})});
    EXPECT_EQ(tr.at(kT0 + Nanos{kS}).position, Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(tr.at(kT0 + Nanos{kS / 2}).position, Eigen::Vector3d(0.5, 1, 1.5));
    EXPECT_EQ(tr.at(kT0).position, Eigen::Vector3d(0, 0, 0));
    EXPECT_EQ(tr.begin(), kT0);
    EXPECT_EQ(tr.end(), kT0 + Nanos{2 * kS});
}

TEST(Trajectory, holds_end_poses_outside_the_range) {
    const Trajectory tr({sample(kT0, {1, 1, 1}, 10), sample(kT0 + Nanos{kS}, {5, 5, 5}, 20)});
    EXPECT_EQ(tr.at(kT0 - Nanos{3600 * kS}).position, Eigen::Vector3d(1, 1, 1));
    EXPECT_EQ(tr.at(kT0 + Nanos{kS + 1}).position, Eigen::Vector3d(5, 5, 5));
    EXPECT_NEAR(rpy_from_quaternion(tr.at(kT0 + Nanos{99 * kS}).attitude).z(), 20 * kDeg, 1e-12);
}

TEST(Trajectory, fixed_pose_everywhere) {
    const Pose p{{1, 2, 3}, quaternion_from_rpy(0.1, 0.2, 0.3)};
    const Trajectory tr = Trajectory::fixed(p);
    EXPECT_TRUE(tr.is_fixed());
    for (GpsTime t : {GpsTime{}, kT0, kT0 + Nanos{86'400 * kS}}) {
        EXPECT_EQ(tr.at(t).position, p.position);
        EXPECT_LT(tr.at(t).attitude.angularDistance(p.attitude), 1e-15);
    }
}

TEST(Trajectory, cubic_reproduces_a_quadratic_path_better_than_linear) {
    // Uneven spacing: 0, 0.7, 1.0, 2.2, 2.5, 4.0 s.
    std::vector<StampedPose> s;
    for (double t : {0.0, 0.7, 1.0, 2.2, 2.5, 4.0}) {
        s.push_back(
            sample(kT0 + Nanos{static_cast<std::int64_t>(std::llround(t * 1e9))}, quadratic(t)));
    }
    const Trajectory lin(s, Interpolation::Linear), cub(s, Interpolation::Cubic);
    double lin_err = 0, cub_err = 0, cub_interior = 0;
    for (int k = 0; k <= 4000; ++k) {
        const double t = k * 1e-3;
        const GpsTime gt = kT0 + Nanos{static_cast<std::int64_t>(k) * 1'000'000};
        const Eigen::Vector3d truth = quadratic(t);
        lin_err = std::max(lin_err, (lin.at(gt).position - truth).norm());
        const double e = (cub.at(gt).position - truth).norm();
        cub_err = std::max(cub_err, e);
        if (t >= 0.7 && t <= 2.5) cub_interior = std::max(cub_interior, e);
    }
    std::printf("quadratic path: max error linear %.4f m, cubic %.2g m, cubic interior %.2g m\n",
                lin_err, cub_err, cub_interior);
    EXPECT_LT(cub_err, 0.5 * lin_err);
    // Tangents (interior and second-order ends) are exact for a parabola, so Hermite
    // reproduces it everywhere.
    EXPECT_LT(cub_interior, 1e-9);
    EXPECT_LT(cub_err, 1e-9);
    // Knots are hit exactly in both modes.
    for (const auto& smp : s) EXPECT_EQ(cub.at(smp.t).position, smp.pose.position);
}

TEST(Trajectory, cubic_follows_a_circle_closer_than_linear) {
    // 100 m radius at 1 rad/s, sampled unevenly (0.15 to 0.4 s); truth is the circle itself.
    const auto circle = [](double t) {
        return Eigen::Vector3d(100 * std::cos(t), 100 * std::sin(t), 0);
    };
    std::vector<StampedPose> s;
    double t = 0;
    for (int i = 0; i < 12; ++i, t += (i % 2 ? 0.15 : 0.4)) {
        s.push_back(
            sample(kT0 + Nanos{static_cast<std::int64_t>(std::llround(t * 1e9))}, circle(t)));
    }
    const Trajectory lin(s, Interpolation::Linear), cub(s, Interpolation::Cubic);
    const std::int64_t span = (lin.end() - lin.begin()).count();
    double lin_err = 0, cub_err = 0;
    for (int k = 0; k <= 2000; ++k) {
        const std::int64_t dt = span / 2000 * k;
        const Eigen::Vector3d truth = circle(static_cast<double>(dt) * 1e-9);
        lin_err = std::max(lin_err, (lin.at(kT0 + Nanos{dt}).position - truth).norm());
        cub_err = std::max(cub_err, (cub.at(kT0 + Nanos{dt}).position - truth).norm());
    }
    std::printf("circle r=100 m: max error linear %.4f m, cubic %.4f m\n", lin_err, cub_err);
    EXPECT_LT(cub_err, 0.1 * lin_err);
}

TEST(Trajectory, cubic_with_two_samples_is_linear) {
    const Trajectory tr({sample(kT0, {0, 0, 0}), sample(kT0 + Nanos{4 * kS}, {4, 8, 0})},
                        Interpolation::Cubic);
    EXPECT_LT((tr.at(kT0 + Nanos{kS}).position - Eigen::Vector3d(1, 2, 0)).norm(), 1e-12);
}

TEST(Trajectory, slerp_crosses_180_degrees_the_short_way) {
    const Trajectory tr(
        {sample(kT0, {0, 0, 0}, 179), sample(kT0 + Nanos{2 * kS}, {0, 0, 0}, -179)});
    const double mid = rpy_from_quaternion(tr.at(kT0 + Nanos{kS}).attitude).z() / kDeg;
    const double quarter = rpy_from_quaternion(tr.at(kT0 + Nanos{kS / 2}).attitude).z() / kDeg;
    const double three_q = rpy_from_quaternion(tr.at(kT0 + Nanos{3 * kS / 2}).attitude).z() / kDeg;
    std::printf("yaw 179 -> -179: quarter %.6f, mid %.6f, three quarters %.6f deg\n", quarter, mid,
                three_q);
    EXPECT_NEAR(std::abs(mid), 180.0, 1e-9);
    EXPECT_NEAR(quarter, 179.5, 1e-9);
    EXPECT_NEAR(three_q, -179.5, 1e-9);
}

TEST(Trajectory, opposite_hemisphere_quaternions_do_not_spin) {
    const Eigen::Quaterniond q = quaternion_from_rpy(0.1, 0.2, 0.3);
    const Eigen::Quaterniond neg(-q.w(), -q.x(), -q.y(), -q.z());
    const Trajectory tr({{kT0, {{0, 0, 0}, q}}, {kT0 + Nanos{kS}, {{0, 0, 0}, neg}}});
    EXPECT_GE(tr.samples()[1].pose.attitude.dot(tr.samples()[0].pose.attitude), 0.0);
    EXPECT_LT(tr.at(kT0 + Nanos{kS / 2}).attitude.angularDistance(q), 1e-12);
}

TEST(Trajectory, attitudes_are_normalised) {
    const Eigen::Quaterniond big(2, 0, 0, 2);
    const Trajectory tr({{kT0, {{0, 0, 0}, big}}});
    EXPECT_NEAR(tr.samples()[0].pose.attitude.norm(), 1.0, 1e-15);
}

TEST(Trajectory, one_ns_after_a_day_is_distinguishable) {
    const GpsTime day = kT0 + Nanos{86'400 * kS};
    const Trajectory tr(
        {sample(kT0, {0, 0, 0}), sample(day, {10, 0, 0}), sample(day + Nanos{2}, {12, 0, 0})});
    EXPECT_EQ(tr.at(day).position.x(), 10.0);
    EXPECT_EQ(tr.at(day + Nanos{1}).position.x(), 11.0);
    EXPECT_EQ(tr.at(day + Nanos{2}).position.x(), 12.0);
    // And in the long first segment 1 ns still moves the pose (10 m / 86 400 s = 1.16e-13 m/ns).
    const GpsTime half = kT0 + Nanos{43'200 * kS};
    EXPECT_EQ(tr.at(half).position.x(), 5.0);
    EXPECT_GT(tr.at(half + Nanos{1}).position.x(), 5.0);
}

TEST(Trajectory, rejects_bad_sample_sets) {
    EXPECT_THROW(Trajectory(std::vector<StampedPose>{}), mirage::ConfigError);
    EXPECT_THROW(Trajectory({sample(kT0, {0, 0, 0}), sample(kT0, {1, 0, 0})}), mirage::ConfigError);
    EXPECT_THROW(Trajectory({sample(kT0, {0, 0, 0}), sample(kT0 - Nanos{1}, {1, 0, 0})}),
                 mirage::ConfigError);
    EXPECT_THROW(Trajectory({{kT0, {{0, 0, 0}, Eigen::Quaterniond(0, 0, 0, 0)}}}),
                 mirage::ConfigError);
    EXPECT_THROW(Trajectory({sample(kT0, {NAN, 0, 0})}), mirage::ConfigError);
}

TEST(Trajectory, hint_access_equals_plain_access) {
    std::mt19937_64 rng(42);
    std::uniform_int_distribution<std::int64_t> step(1, 3 * kS);
    std::uniform_real_distribution<double> coord(-100, 100), angle(-180, 180);
    std::vector<StampedPose> s;
    GpsTime t = kT0;
    for (int i = 0; i < 500; ++i) {
        t += Nanos{step(rng)};
        s.push_back(
            {t,
             {{coord(rng), coord(rng), coord(rng)},
              quaternion_from_rpy(angle(rng) * kDeg, angle(rng) * kDeg * 0.4, angle(rng) * kDeg)}});
    }
    for (Interpolation interp : {Interpolation::Linear, Interpolation::Cubic}) {
        const Trajectory tr(s, interp);
        const std::int64_t span = (tr.end() - tr.begin()).count();
        std::uniform_int_distribution<std::int64_t> when(-span / 20, span + span / 20);
        std::vector<GpsTime> times(10'000);
        for (auto& x : times) x = tr.begin() + Nanos{when(rng)};
        std::vector<GpsTime> sorted = times;
        std::sort(sorted.begin(), sorted.end());
        for (const auto* order : {&times, &sorted}) {
            std::size_t hint = 0;
            for (GpsTime x : *order) {
                const Pose a = tr.at(x), b = tr.at(x, hint);
                ASSERT_EQ(a.position, b.position);
                ASSERT_EQ(a.attitude.coeffs(), b.attitude.coeffs());
            }
        }
        // A stale or absurd hint is harmless.
        std::size_t bad = 1'000'000;
        EXPECT_EQ(tr.at(sorted[5000], bad).position, tr.at(sorted[5000]).position);
    }
}
