// SPDX-License-Identifier: Apache-2.0
// IMU packets (§2.6) and readings derived from the trajectory, against closed forms.
#include "mirage/ouster/imu.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace mirage::ouster {
namespace {

const core::GpsTime kT0 = core::GpsTime(std::chrono::seconds(1'000'000'000));

core::StampedPose at(double s, Eigen::Vector3d p, double yaw_rad) {
    return {kT0 + core::Nanos(std::llround(s * 1e9)),
            core::Pose{p, core::quaternion_from_rpy(0, 0, yaw_rad)}};
}

TEST(OusterImu, packet_round_trip_is_bit_exact_and_sized_48) {
    ImuPacket p;
    p.sys_ns = 765719656040;
    p.accel_ns = 765719870590;
    p.gyro_ns = 765720093360;
    p.accel_g = {0.0083f, 0.1108f, 1.021f};
    p.gyro_dps = {0.183f, 0.412f, -0.458f};
    std::array<std::uint8_t, kImuPacketBytes> b{};
    ASSERT_TRUE(encode_imu_packet(p, b));
    EXPECT_FALSE(encode_imu_packet(p, std::span(b).first(47)));
    ImuPacket q;
    ASSERT_TRUE(decode_imu_packet(b, q));
    EXPECT_EQ(q.sys_ns, p.sys_ns);
    EXPECT_EQ(q.accel_ns, p.accel_ns);
    EXPECT_EQ(q.gyro_ns, p.gyro_ns);
    EXPECT_EQ(q.accel_g, p.accel_g);
    EXPECT_EQ(q.gyro_dps, p.gyro_dps);
    std::vector<std::uint8_t> big(49);
    EXPECT_FALSE(decode_imu_packet(big, q));
    EXPECT_FALSE(decode_imu_packet({}, q));
}

TEST(OusterImu, static_pose_reads_plus_one_g_up_and_no_rotation) {
    const Descriptor d = make_descriptor(ProductLine::OS1, 64, {1024, 10}, Profile::Legacy);
    const auto traj =
        core::Trajectory::fixed(core::Pose{{10, 20, 3}, core::quaternion_from_rpy(0, 0, 1.0)});
    const ImuReading r = imu_reading(traj, core::Mount{}, d, kT0);
    EXPECT_NEAR(r.accel_g.x(), 0.0, 1e-12);
    EXPECT_NEAR(r.accel_g.y(), 0.0, 1e-12);
    EXPECT_NEAR(r.accel_g.z(), 1.0, 1e-12);
    EXPECT_NEAR(r.gyro_dps.norm(), 0.0, 1e-12);

    // Sensor mounted upside down (roll 180°): gravity reads −1 g on the IMU z axis.
    core::Mount flipped;
    flipped.boresight = core::quaternion_from_rpy(std::numbers::pi, 0, 0);
    EXPECT_NEAR(imu_reading(traj, flipped, d, kT0).accel_g.z(), -1.0, 1e-12);
}

TEST(OusterImu, constant_yaw_rate_reads_on_gyro_z) {
    const Descriptor d = make_descriptor(ProductLine::OS2, 128, {1024, 10}, Profile::Legacy);
    const double rate = 0.5;  // rad/s, counter-clockwise seen from above
    std::vector<core::StampedPose> s;
    for (int i = 0; i <= 40; ++i) s.push_back(at(0.05 * i, {0, 0, 0}, rate * 0.05 * i));
    const core::Trajectory traj(s, core::Interpolation::Linear);
    const ImuReading r = imu_reading(traj, core::Mount{}, d, kT0 + std::chrono::milliseconds(1003));
    // IMU z = sensor z = lidar z (180° about z between them keeps z).
    EXPECT_NEAR(r.gyro_dps.z(), rate * 180.0 / std::numbers::pi, 1e-6);
    EXPECT_NEAR(r.gyro_dps.x(), 0.0, 1e-9);
    EXPECT_NEAR(r.gyro_dps.y(), 0.0, 1e-9);
    // The IMU sits off the rotation axis: centripetal ω²·|r| toward the axis, in the IMU frame.
    const double r_m = std::hypot(6.253e-3, -11.775e-3);
    EXPECT_NEAR(r.accel_g.head<2>().norm(), rate * rate * r_m / kStandardGravity, 1e-6);
    EXPECT_NEAR(r.accel_g.z(), 1.0, 1e-9);
}

TEST(OusterImu, forward_acceleration_reads_minus_x_in_the_imu_frame) {
    // Constant 2 m/s² along world x = body x (yaw 0). The lidar frame is the body frame; the
    // IMU / Ouster sensor frame is turned 180° about z, so it reads −2/g on x.
    const Descriptor d = make_descriptor(ProductLine::OS1, 32, {512, 10}, Profile::Legacy);
    std::vector<core::StampedPose> s;
    for (int i = 0; i <= 20; ++i) {
        const double t = 0.1 * i;
        s.push_back(at(t, {t * t, 0, 0}, 0));  // x = ½·2·t²
    }
    const core::Trajectory traj(s, core::Interpolation::Cubic);
    const ImuReading r = imu_reading(traj, core::Mount{}, d, kT0 + std::chrono::milliseconds(1000));
    EXPECT_NEAR(r.accel_g.x(), -2.0 / kStandardGravity, 1e-6);
    EXPECT_NEAR(r.accel_g.y(), 0.0, 1e-9);
    EXPECT_NEAR(r.accel_g.z(), 1.0, 1e-9);
}

}  // namespace
}  // namespace mirage::ouster
