// SPDX-License-Identifier: Apache-2.0
// Helpers shared by the navpose tests.
#pragma once
#include <Eigen/Geometry>
#include <cstdint>

#include "mirage/core/pose.hpp"
#include "mirage/core/time.hpp"

namespace mirage::navpose::test {

// GPS time `ms` milliseconds after the GPS epoch.
inline core::GpsTime T(std::int64_t ms) { return core::GpsTime(core::Nanos(ms * 1'000'000)); }
// A pure heading (yaw) attitude, rad.
inline Eigen::Quaterniond yaw(double rad) { return core::quaternion_from_rpy(0, 0, rad); }

}  // namespace mirage::navpose::test
