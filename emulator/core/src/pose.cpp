// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/pose.hpp"

#include <cmath>
#include <numbers>

namespace mirage::core {
namespace {

// Maps atan2's −π onto π so angles lie in (−π, π].
double wrap_pi(double a) { return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a; }

}  // namespace

Eigen::Quaterniond quaternion_from_rpy(double roll, double pitch, double yaw) {
    return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
        .normalized();
}

Eigen::Vector3d rpy_from_quaternion(const Eigen::Quaterniond& q) {
    const Eigen::Matrix3d r = q.normalized().toRotationMatrix();
    // R = Rz(y)·Ry(p)·Rx(r): first column is (cp·cy, cp·sy, −sp).
    const double cp = std::hypot(r(0, 0), r(1, 0));
    const double pitch = std::atan2(-r(2, 0), cp);
    // At gimbal lock (|pitch| = 90° to rounding) yaw and roll turn about the same axis and the
    // first column no longer fixes yaw; take it from the second column (roll = 0 there). Just
    // above the threshold yaw is ill-conditioned but the roll below absorbs its error.
    constexpr double kLock = 1e-15;
    const double yaw = cp > kLock ? std::atan2(r(1, 0), r(0, 0)) : std::atan2(-r(0, 1), r(1, 1));
    // Roll from what remains once yaw and pitch are taken out, so the three angles always
    // rebuild R even where yaw alone is ill-conditioned.
    const Eigen::Matrix3d rest = (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).inverse() *
                                  Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).inverse())
                                     .toRotationMatrix() *
                                 r;
    const double roll = std::atan2(rest(2, 1), rest(2, 2));
    return {wrap_pi(roll), pitch, wrap_pi(yaw)};
}

}  // namespace mirage::core
