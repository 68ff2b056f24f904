// SPDX-License-Identifier: Apache-2.0
// Motion distortion: a sensor moving at 30 m/s and yawing at 90°/s casts every pulse from the
// pose at its own firing time, so each point lies on the geometry, and transforming it back
// with the true pose at that time recovers the fired direction (≤ 1 mm).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

constexpr double kSpeed = 30.0, kYawRate = std::numbers::pi / 2, kHeight = 2.0;

core::Pose truth(core::Nanos t) {
    const double s = double(t.count()) * 1e-9;
    return {{kSpeed * s, 0.0, kHeight}, core::quaternion_from_rpy(0, 0, kYawRate * s)};
}

TEST(PipelineMotion, every_point_lies_on_geometry_at_its_firing_time) {
    scene::Scene scene = plane_scene(2000.0, Eigen::Affine3d::Identity());
    render::EmbreeRenderer r(scene);
    std::vector<Eigen::Vector3f> dirs;
    for (int a = 0; a < 360; ++a) {
        const double az = a * std::numbers::pi / 180.0;
        dirs.push_back(unit(std::cos(az), -std::sin(az), -0.35));
    }
    auto sensor = test_sensor(std::make_shared<FanPattern>(dirs, 10'000));  // 100 kHz
    // Samples every 10 ms; linear position and constant-axis slerp are exact for this motion.
    std::vector<core::StampedPose> samples;
    for (int i = 0; i <= 300; ++i) {
        const core::Nanos t(std::int64_t(i) * 10'000'000);
        samples.push_back({core::GpsTime(t), truth(t)});
    }
    core::Trajectory traj(samples, core::Interpolation::Linear);
    render::RenderOptions opt;
    opt.noise = false;
    opt.duration = std::chrono::seconds(3);
    VectorSink sink;
    render::render({scene, r, sensor, traj, {}, {}, opt}, sink);
    ASSERT_EQ(sink.points.size(), 300'000u);
    double worst_plane = 0, worst_dir = 0;
    for (const auto& p : sink.points) {
        worst_plane = std::max(worst_plane, std::abs(p.z));
        const core::Pose pose = truth(p.t.time_since_epoch());
        const Eigen::Vector3d local = pose.inverse().apply({p.x, p.y, p.z});
        const Eigen::Vector3d fired = dirs[p.pulse % dirs.size()].cast<double>().normalized();
        worst_dir = std::max(worst_dir, (local - double(p.range_m) * fired).norm());
    }
    std::printf("moving sensor: worst distance to plane %.4f mm, worst re-projection %.4f mm\n",
                worst_plane * 1e3, worst_dir * 1e3);
    EXPECT_LE(worst_plane, 1e-3);
    EXPECT_LE(worst_dir, 1e-3);
    // The motion is real: a whole-frame pose would misplace points by metres.
    const core::Pose frame = truth(core::Nanos(0));
    double worst_frame = 0;
    for (const auto& p : sink.points) {
        const Eigen::Vector3d wrong = frame.apply(
            double(p.range_m) * dirs[p.pulse % dirs.size()].cast<double>().normalized());
        worst_frame = std::max(worst_frame, (wrong - Eigen::Vector3d(p.x, p.y, p.z)).norm());
    }
    EXPECT_GT(worst_frame, 10.0);
}

TEST(PipelineMotion, lever_arm_and_boresight_place_and_point_the_sensor) {
    // Wall x = 50 facing the origin.
    Eigen::Affine3d wall = Eigen::Affine3d::Identity();
    wall.translate(Eigen::Vector3d(50, 0, 0));
    wall.rotate(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()));
    const scene::Scene scene = plane_scene(400.0, wall);
    render::EmbreeRenderer r(scene);
    auto sensor = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, 1000));
    // Platform at (10, 20, 0) facing north; sensor 1 m forward and 2 m up, turned 90° right.
    const core::Pose platform{{10, 20, 0}, core::quaternion_from_rpy(0, 0, std::numbers::pi / 2)};
    core::Mount mount;
    mount.lever_arm_m = {1, 0, 2};
    mount.boresight = core::quaternion_from_rpy(0, 0, -std::numbers::pi / 2);
    render::RenderOptions opt;
    opt.noise = false;
    opt.duration = core::Nanos(1000);
    VectorSink sink;
    render::render({scene, r, sensor, core::Trajectory::fixed(platform), mount, {}, opt}, sink);
    ASSERT_EQ(sink.points.size(), 1u);
    const auto& p = sink.points[0];
    EXPECT_NEAR(p.x, 50.0, 1e-4);
    EXPECT_NEAR(p.y, 21.0, 1e-4);
    EXPECT_NEAR(p.z, 2.0, 1e-4);
    EXPECT_NEAR(p.range_m, 40.0, 1e-4);
}

}  // namespace
}  // namespace mirage::test
