// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Geometry>

#include "mirage/core/time.hpp"

namespace mirage::core {

// Frames. World: local ENU (x east, y north, z up) in metres relative to the scene's
// double-precision anchor. Body and sensor: FLU (x forward, y left, z up; ROS REP-103).
// A Pose maps body coordinates to world: p_world = position + attitude * p_body.
struct Pose {
    Eigen::Vector3d position{Eigen::Vector3d::Zero()};
    Eigen::Quaterniond attitude{Eigen::Quaterniond::Identity()};

    Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return position + attitude * p; }
    Pose operator*(const Pose& o) const {
        return {position + attitude * o.position, (attitude * o.attitude).normalized()};
    }
    Pose inverse() const {
        Eigen::Quaterniond qi = attitude.conjugate();
        return {-(qi * position), qi};
    }
};

struct StampedPose {
    GpsTime t;
    Pose pose;
};

// Attitude from roll/pitch/yaw in radians: R = Rz(yaw) · Ry(pitch) · Rx(roll), body FLU into
// world ENU; yaw 0 faces east, positive yaw turns counter-clockwise (left) seen from above.
Eigen::Quaterniond quaternion_from_rpy(double roll, double pitch, double yaw);
// Inverse of quaternion_from_rpy; yaw in (−π, π].
Eigen::Vector3d rpy_from_quaternion(const Eigen::Quaterniond& q);

// Sensor mounting on the platform: lever arm (sensor origin in body frame, m) and
// boresight (sensor attitude in body frame). sensor_in_world = platform_pose * mount.
struct Mount {
    Eigen::Vector3d lever_arm_m{Eigen::Vector3d::Zero()};
    Eigen::Quaterniond boresight{Eigen::Quaterniond::Identity()};
    Pose as_pose() const { return {lever_arm_m, boresight}; }
};

}  // namespace mirage::core
