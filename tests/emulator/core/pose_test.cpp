// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/pose.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_units.hpp"

using namespace mirage::core;

namespace {

constexpr double kPi = std::numbers::pi;
using mirage::test::kDeg;

Eigen::Matrix3d rx(double a) {
    Eigen::Matrix3d m;
    m << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
    return m;
}
Eigen::Matrix3d ry(double a) {
    Eigen::Matrix3d m;
    m << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
    return m;
}
Eigen::Matrix3d rz(double a) {
    Eigen::Matrix3d m;
    m << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
    return m;
}

// Rotation angle between two attitudes, rad.
double angle_between(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
    return a.angularDistance(b);
}

}  // namespace

TEST(Pose, rpy_matches_rz_ry_rx_matrix_product) {
    for (double r : {-2.0, -0.3, 0.0, 0.7, 3.0})
        for (double p : {-1.2, 0.0, 0.4, 1.5})
            for (double y : {-3.1, -1.0, 0.0, 2.0, 3.14}) {
                const Eigen::Matrix3d expected = rz(y) * ry(p) * rx(r);
                EXPECT_LT((quaternion_from_rpy(r, p, y).toRotationMatrix() - expected).norm(),
                          1e-14);
            }
}

TEST(Pose, yaw_turns_forward_counter_clockwise_from_east) {
    const Eigen::Vector3d fwd = quaternion_from_rpy(0, 0, kPi / 2) * Eigen::Vector3d::UnitX();
    EXPECT_LT((fwd - Eigen::Vector3d(0, 1, 0)).norm(), 1e-15);  // east -> north
    // Positive pitch about the FLU y (left) axis lowers the nose.
    const Eigen::Vector3d nose = quaternion_from_rpy(0, 30 * kDeg, 0) * Eigen::Vector3d::UnitX();
    EXPECT_LT((nose - Eigen::Vector3d(std::cos(30 * kDeg), 0, -0.5)).norm(), 1e-15);
    // Positive roll about forward lifts the left side.
    const Eigen::Vector3d left = quaternion_from_rpy(kPi / 2, 0, 0) * Eigen::Vector3d::UnitY();
    EXPECT_LT((left - Eigen::Vector3d(0, 0, 1)).norm(), 1e-15);
}

TEST(Pose, rpy_round_trips_over_a_grid) {
    double worst = 0;
    for (int r = -179; r <= 180; r += 7)
        for (int p = -89; p <= 89; p += 4)
            for (int y = -179; y <= 180; y += 11) {
                const Eigen::Vector3d in(r * kDeg, p * kDeg, y * kDeg);
                const Eigen::Vector3d out =
                    rpy_from_quaternion(quaternion_from_rpy(in.x(), in.y(), in.z()));
                worst = std::max(worst, (out - in).cwiseAbs().maxCoeff());
            }
    std::printf("rpy round trip worst error: %.3g rad\n", worst);
    EXPECT_LT(worst, 1e-12);
}

TEST(Pose, yaw_plus_minus_180_comes_back_as_plus_180) {
    for (double yaw : {kPi, -kPi}) {
        const Eigen::Vector3d out = rpy_from_quaternion(quaternion_from_rpy(0.1, 0.2, yaw));
        EXPECT_NEAR(out.z(), kPi, 1e-12);
        EXPECT_NEAR(out.x(), 0.1, 1e-12);
        EXPECT_NEAR(out.y(), 0.2, 1e-12);
    }
    const Eigen::Vector3d out = rpy_from_quaternion(quaternion_from_rpy(0, 0, -179.5 * kDeg));
    EXPECT_NEAR(out.z(), -179.5 * kDeg, 1e-12);
}

TEST(Pose, pitch_near_vertical_is_finite_and_rebuilds_the_rotation) {
    double worst = 0;
    for (double sign : {1.0, -1.0})
        for (double delta : {1e-2, 1e-5, 1e-8, 1e-10, 1e-13, 0.0})
            for (double r : {-2.5, 0.0, 0.3})
                for (double y : {-3.0, 0.0, 1.2, kPi}) {
                    const double p = sign * (kPi / 2 - delta);
                    const Eigen::Quaterniond q = quaternion_from_rpy(r, p, y);
                    const Eigen::Vector3d a = rpy_from_quaternion(q);
                    ASSERT_TRUE(a.allFinite()) << p;
                    EXPECT_NEAR(a.y(), p, 1e-7);
                    EXPECT_GT(a.z(), -kPi);
                    EXPECT_LE(a.z(), kPi);
                    worst =
                        std::max(worst, angle_between(quaternion_from_rpy(a.x(), a.y(), a.z()), q));
                }
    std::printf("near-vertical pitch: worst rebuilt-rotation error %.3g rad\n", worst);
    EXPECT_LT(worst, 1e-12);
    // Away from the lock the angles themselves come back.
    const Eigen::Vector3d a = rpy_from_quaternion(quaternion_from_rpy(0.3, 89.9 * kDeg, 1.2));
    EXPECT_NEAR(a.x(), 0.3, 1e-9);
    EXPECT_NEAR(a.z(), 1.2, 1e-9);
}

TEST(Pose, negated_quaternion_gives_the_same_angles) {
    const Eigen::Quaterniond q = quaternion_from_rpy(0.4, -0.7, 2.9);
    const Eigen::Quaterniond neg(-q.w(), -q.x(), -q.y(), -q.z());
    EXPECT_LT((rpy_from_quaternion(q) - rpy_from_quaternion(neg)).norm(), 1e-14);
    // And a non-unit quaternion is normalised first.
    const Eigen::Quaterniond scaled(3 * q.w(), 3 * q.x(), 3 * q.y(), 3 * q.z());
    EXPECT_LT((rpy_from_quaternion(q) - rpy_from_quaternion(scaled)).norm(), 1e-14);
}

TEST(Pose, compose_with_inverse_is_identity) {
    const Pose a{{10, -3, 2}, quaternion_from_rpy(0.1, 0.2, 0.3)};
    const Pose id = a * a.inverse();
    EXPECT_LT(id.position.norm(), 1e-14);
    EXPECT_LT(angle_between(id.attitude, Eigen::Quaterniond::Identity()), 1e-14);
    const Eigen::Vector3d p(1, 2, 3);
    EXPECT_LT((a.inverse().apply(a.apply(p)) - p).norm(), 1e-14);
}
