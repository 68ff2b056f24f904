// SPDX-License-Identifier: Apache-2.0
#include "mirage/ouster/imu.hpp"

#include <Eigen/Geometry>
#include <bit>
#include <cmath>
#include <numbers>

#include "byte_io.hpp"

namespace mirage::ouster {
namespace {

Eigen::Matrix3d rotation_of(const std::array<double, 16>& m) {
    Eigen::Matrix3d r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r(i, j) = m[static_cast<std::size_t>(4 * i + j)];
    return r;
}
Eigen::Vector3d translation_m(const std::array<double, 16>& m) {
    return Eigen::Vector3d(m[3], m[7], m[11]) * 1e-3;
}

void put_f32(std::uint8_t* p, float v) { put_u32(p, std::bit_cast<std::uint32_t>(v)); }
float get_f32(const std::uint8_t* p) { return std::bit_cast<float>(get_u32(p)); }

}  // namespace

bool encode_imu_packet(const ImuPacket& p, std::span<std::uint8_t> out) {
    if (out.size() != kImuPacketBytes) return false;
    std::uint8_t* b = out.data();
    put_u64(b, p.sys_ns);
    put_u64(b + 8, p.accel_ns);
    put_u64(b + 16, p.gyro_ns);
    for (std::size_t i = 0; i < 3; ++i) {
        put_f32(b + 24 + 4 * i, p.accel_g[i]);
        put_f32(b + 36 + 4 * i, p.gyro_dps[i]);
    }
    return true;
}

bool decode_imu_packet(std::span<const std::uint8_t> bytes, ImuPacket& out) {
    if (bytes.size() != kImuPacketBytes) return false;
    const std::uint8_t* b = bytes.data();
    out.sys_ns = get_u64(b);
    out.accel_ns = get_u64(b + 8);
    out.gyro_ns = get_u64(b + 16);
    for (std::size_t i = 0; i < 3; ++i) {
        out.accel_g[i] = get_f32(b + 24 + 4 * i);
        out.gyro_dps[i] = get_f32(b + 36 + 4 * i);
    }
    return true;
}

ImuReading imu_reading(const core::Trajectory& trajectory, const core::Mount& mount,
                       const Descriptor& d, core::GpsTime t, core::Nanos step) {
    // IMU pose in the lidar frame (= Mirage's sensor frame): sensor←lidar is L, sensor←imu is I.
    const Eigen::Matrix3d rl = rotation_of(d.lidar_to_sensor);
    const Eigen::Matrix3d lidar_r_imu = rl.transpose() * rotation_of(d.imu_to_sensor);
    const Eigen::Vector3d lidar_p_imu =
        rl.transpose() * (translation_m(d.imu_to_sensor) - translation_m(d.lidar_to_sensor));
    const core::Pose imu_in_body =
        mount.as_pose() * core::Pose{lidar_p_imu, Eigen::Quaterniond(lidar_r_imu)};

    const auto world_imu = [&](core::GpsTime at) { return trajectory.at(at) * imu_in_body; };
    const core::Pose before = world_imu(t - step), now = world_imu(t), after = world_imu(t + step);
    const double h = std::chrono::duration<double>(step).count();

    const Eigen::Vector3d accel_world =
        (after.position - 2.0 * now.position + before.position) / (h * h);
    const Eigen::Vector3d specific_force =
        accel_world + Eigen::Vector3d(0, 0, kStandardGravity);  // a − g, g pointing down

    const Eigen::AngleAxisd delta(after.attitude * before.attitude.conjugate());
    const Eigen::Vector3d omega_world = delta.axis() * (delta.angle() / (2.0 * h));

    const Eigen::Quaterniond world_to_imu = now.attitude.conjugate();
    ImuReading r;
    r.accel_g = world_to_imu * specific_force / kStandardGravity;
    r.gyro_dps = world_to_imu * omega_world * (180.0 / std::numbers::pi);
    return r;
}

}  // namespace mirage::ouster
