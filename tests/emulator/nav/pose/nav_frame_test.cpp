// SPDX-License-Identifier: Apache-2.0
#include "mirage/navpose/nav_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "mirage/core/error.hpp"
#include "mirage/core/georef.hpp"
#include "mirage/core/pose.hpp"
#include "test_units.hpp"

using namespace mirage;
using navpose::NavFrame;

namespace {
using mirage::test::kDeg;
// The demo town's georeference: UTM 32N, anchor on the central meridian (9° E).
core::Georef town() { return core::Georef::projected(32632, {500000.0, 5000000.0, 200.0}); }

double angle_between(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
    return a.angularDistance(b);
}
}  // namespace

TEST(NavFrame, utm_positions_agree_with_proj_within_a_millimetre) {
    const core::Georef g = town();
    const NavFrame f = NavFrame::from_georef(g);
    const Eigen::Vector3d anchor_geo = g.geodetic_from_local(Eigen::Vector3d::Zero());
    for (const Eigen::Vector3d& local :
         {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(480, -730, 35), Eigen::Vector3d(-950, 990, -20),
          Eigen::Vector3d(30000, 20000, 5)}) {
        const Eigen::Vector3d geo = g.geodetic_from_local(local);
        const Eigen::Vector3d ours = f.local_from_geodetic(geo.x(), geo.y(), geo.z());
        EXPECT_LT((ours - local).norm(), 1e-3) << local.transpose();
        const Eigen::Vector3d back = f.geodetic_from_local(local);
        EXPECT_NEAR(back.x(), geo.x(), 1e-9);
        EXPECT_NEAR(back.y(), geo.y(), 1e-9);
        EXPECT_NEAR(back.z(), geo.z(), 1e-9);
    }
    EXPECT_NEAR(anchor_geo.y(), 9.0, 1e-9);  // central meridian of zone 32
}

TEST(NavFrame, convergence_is_zero_on_the_central_meridian_and_follows_dlon_sin_lat) {
    const NavFrame f = NavFrame::from_georef(town());
    EXPECT_NEAR(f.convergence_rad(45.0, 9.0), 0.0, 1e-12);
    // First-order closed form γ ≈ Δλ·sin φ (good to ~1e-4 relative at 1° from the meridian).
    const double g = f.convergence_rad(45.0, 10.0);
    EXPECT_NEAR(g, 1.0 * kDeg * std::sin(45.0 * kDeg), 2e-4 * kDeg);
    EXPECT_GT(g, 0.0);  // east of the central meridian in the north: grid north is east of true
    EXPECT_LT(f.convergence_rad(45.0, 8.0), 0.0);
}

TEST(NavFrame, ned_euler_maps_to_the_local_flu_enu_attitude_in_closed_form) {
    const NavFrame f = NavFrame::from_georef(town());
    const double lat = 45.1, lon = 9.0;  // on the central meridian: true north = grid north
    // Heading 0: forward is north (+y), left is west (−x).
    Eigen::Quaterniond q = f.local_attitude(0, 0, 0, lat, lon);
    EXPECT_LT((q * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
    EXPECT_LT((q * Eigen::Vector3d::UnitY() + Eigen::Vector3d::UnitX()).norm(), 1e-12);
    // Heading 90°: forward is east.
    q = f.local_attitude(0, 0, 90 * kDeg, lat, lon);
    EXPECT_LT((q * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX()).norm(), 1e-12);
    // Pitch +10° is nose up; roll +10° puts the right side down, so the left side goes up.
    q = f.local_attitude(0, 10 * kDeg, 90 * kDeg, lat, lon);
    EXPECT_NEAR((q * Eigen::Vector3d::UnitX()).z(), std::sin(10 * kDeg), 1e-12);
    q = f.local_attitude(10 * kDeg, 0, 90 * kDeg, lat, lon);
    EXPECT_NEAR((q * Eigen::Vector3d::UnitY()).z(), std::sin(10 * kDeg), 1e-12);
    // Heading 350° and −10° are the same attitude.
    EXPECT_LT(angle_between(f.local_attitude(0.1, 0.2, 350 * kDeg, lat, lon),
                            f.local_attitude(0.1, 0.2, -10 * kDeg, lat, lon)),
              1e-12);
    // The core's roll/pitch/yaw convention (yaw from east, CCW; FLU pitch nose-down positive).
    for (double h : {0.0, 30.0, 135.0, 271.0}) {
        const Eigen::Quaterniond ours = f.local_attitude(0.05, 0.1, h * kDeg, lat, lon);
        const Eigen::Quaterniond core_q =
            core::quaternion_from_rpy(0.05, -0.1, std::numbers::pi / 2 - h * kDeg);
        EXPECT_LT(angle_between(ours, core_q), 1e-12) << h;
    }
}

TEST(NavFrame, a_true_heading_off_the_central_meridian_is_turned_by_the_convergence) {
    const NavFrame f = NavFrame::from_georef(town());
    const double lat = 45.0, lon = 10.0;
    const double gamma = f.convergence_rad(lat, lon);
    // Facing true north, the body points to grid bearing −γ: x = −sin γ, y = cos γ.
    const Eigen::Vector3d fwd = f.local_attitude(0, 0, 0, lat, lon) * Eigen::Vector3d::UnitX();
    EXPECT_NEAR(fwd.x(), -std::sin(gamma), 1e-12);
    EXPECT_NEAR(fwd.y(), std::cos(gamma), 1e-12);
    const Eigen::Vector3d v = f.local_velocity({1, 0, 0}, lat, lon);
    EXPECT_NEAR(v.x(), -std::sin(gamma), 1e-12);
    EXPECT_NEAR(v.y(), std::cos(gamma), 1e-12);
    EXPECT_NEAR(f.local_velocity({0, 0, 2}, lat, lon).z(), -2.0, 1e-12);  // down is −up
}

TEST(NavFrame, euler_and_velocity_round_trip_at_random_attitudes) {
    const NavFrame f = NavFrame::from_georef(town());
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 1000; ++i) {
        const double lat = 45 + 0.5 * u(rng), lon = 9 + 2.5 * u(rng);
        const double roll = u(rng) * 3.0, pitch = u(rng) * 1.5, heading = (u(rng) + 1) * 3.14;
        const Eigen::Quaterniond q = f.local_attitude(roll, pitch, heading, lat, lon);
        const Eigen::Vector3d e = f.ned_euler(q, lat, lon);
        EXPECT_LT(angle_between(f.local_attitude(e.x(), e.y(), e.z(), lat, lon), q), 1e-9);
        EXPECT_GE(e.z(), 0.0);
        EXPECT_LT(e.z(), 2 * std::numbers::pi);
        const Eigen::Vector3d vn(u(rng) * 30, u(rng) * 30, u(rng) * 3);
        EXPECT_LT((f.ned_velocity(f.local_velocity(vn, lat, lon), lat, lon) - vn).norm(), 1e-12);
    }
}

TEST(NavFrame, sample_and_pose_are_inverse) {
    const NavFrame f = NavFrame::from_georef(town());
    core::Pose p{{312.5, -48.25, 3.5}, core::quaternion_from_rpy(0.02, -0.03, 1.2)};
    const nav::NavSample s = f.sample(p, {3, 4, 0});
    EXPECT_TRUE(s.has(nav::NavSample::kPosition | nav::NavSample::kAttitude));
    const core::Pose back = f.pose(s);
    EXPECT_LT((back.position - p.position).norm(), 1e-6);
    EXPECT_LT(angle_between(back.attitude, p.attitude), 1e-12);
    EXPECT_NEAR(s.velocity_ned_mps.norm(), 5.0, 1e-12);
}

TEST(NavFrame, tangent_plane_has_true_north_and_its_origin_at_zero) {
    const NavFrame f = NavFrame::tangent_plane(48.1173, 11.5167, 545.4);
    EXPECT_LT(f.local_from_geodetic(48.1173, 11.5167, 545.4).norm(), 1e-9);
    const Eigen::Vector3d p = f.local_from_geodetic(48.1173 + 1e-4, 11.5167, 545.4);
    EXPECT_NEAR(p.y(), 11.12, 0.02);  // 1e-4° of latitude ≈ 11.12 m north
    EXPECT_NEAR(p.x(), 0.0, 1e-6);
    EXPECT_EQ(f.convergence_rad(48.2, 11.6), 0.0);
}

TEST(NavFrame, rejects_scenes_it_cannot_map_with_a_clear_message) {
    try {
        (void)NavFrame::from_georef(core::Georef());
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("EPSG:0"), std::string::npos) << e.what();
    }
    EXPECT_THROW((void)NavFrame::tangent_plane(91, 0, 0), ConfigError);
}
