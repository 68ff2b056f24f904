// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "mirage/core/pose.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/ouster/descriptor.hpp"

namespace mirage::ouster {

inline constexpr std::size_t kImuPacketBytes = 48;   // LEGACY IMU profile (§2.6)
inline constexpr double kStandardGravity = 9.80665;  // m/s² per g

struct ImuPacket {
    std::uint64_t sys_ns = 0, accel_ns = 0, gyro_ns = 0;
    std::array<float, 3> accel_g{};   // linear acceleration (specific force), g, IMU frame
    std::array<float, 3> gyro_dps{};  // angular velocity, °/s, IMU frame
};

// `out` must hold kImuPacketBytes (else false, nothing written).
bool encode_imu_packet(const ImuPacket& p, std::span<std::uint8_t> out);
// False (and `out` untouched) unless bytes.size() == kImuPacketBytes.
bool decode_imu_packet(std::span<const std::uint8_t> bytes, ImuPacket& out);

struct ImuReading {
    Eigen::Vector3d accel_g = Eigen::Vector3d::Zero();
    Eigen::Vector3d gyro_dps = Eigen::Vector3d::Zero();
};

// What the unit's IMU reads at time t when the platform follows `trajectory` and Mirage's sensor
// frame (= Ouster's lidar frame, see presets) is mounted with `mount`. Pure function.
// Accelerometer: specific force a − g of the IMU's own position (second central difference over
// ±step, so the lever arm's centripetal term is included), g = (0, 0, −9.80665) m/s² in ENU, at
// rest it reads +1 g up. Gyro: rotation between t − step and t + step (central difference of the
// attitude), in the IMU frame at t. IMU frame: imu_to_sensor and lidar_to_sensor of `d`
// (IMU axes = Ouster sensor axes = lidar axes turned 180° about z by default).
ImuReading imu_reading(const core::Trajectory& trajectory, const core::Mount& mount,
                       const Descriptor& d, core::GpsTime t,
                       core::Nanos step = std::chrono::milliseconds(5));

}  // namespace mirage::ouster
