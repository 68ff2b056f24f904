// SPDX-License-Identifier: Apache-2.0
// A DIS state as a NavSample (docs/dis.md §4), against closed forms: the local north-east-down
// axes written out from latitude and longitude; a level platform facing north on the equator at
// longitude 0 and facing east at longitude 90°; any attitude at Munich; and the dead-reckoned
// velocity against the position's central difference for every algorithm.
#include "mirage/dis/dis_sample.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "dis_fixtures.hpp"

namespace mirage::dis {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr double kA = 6'378'137.0;  // WGS84 equatorial radius, m
constexpr double kDeg = std::numbers::pi / 180;

// North, east and down at a latitude and longitude, in ECEF: the columns of R_ecef_ned.
Matrix3d ecef_from_ned(double lat_deg, double lon_deg) {
    const double p = lat_deg * kDeg, l = lon_deg * kDeg;
    Matrix3d r;
    r.col(0) << -std::sin(p) * std::cos(l), -std::sin(p) * std::sin(l), std::cos(p);
    r.col(1) << -std::sin(l), std::cos(l), 0;
    r.col(2) << -std::cos(p) * std::cos(l), -std::cos(p) * std::sin(l), -std::sin(p);
    return r;
}

TEST(DisSample, a_level_platform_on_the_equator_faces_where_its_axes_point) {
    Kinematics north;
    north.location = {kA, 0, 0};
    north.body_to_ecef = body_to_ecef(0, -std::numbers::pi / 2, 0);
    north.velocity = {0, 0, 5};  // 5 m/s north
    const auto s = to_sample(north, core::GpsTime{});
    EXPECT_NEAR(s.lat_deg, 0, 1e-12);
    EXPECT_NEAR(s.lon_deg, 0, 1e-12);
    EXPECT_NEAR(s.height_m, 0, 1e-6);
    EXPECT_NEAR(s.roll_rad, 0, 1e-12);
    EXPECT_NEAR(s.pitch_rad, 0, 1e-12);
    EXPECT_NEAR(s.heading_rad, 0, 1e-12);
    EXPECT_LT((s.velocity_ned_mps - Vector3d(5, 0, 0)).norm(), 1e-12);
    EXPECT_EQ(s.source, nav::Protocol::Dis);
    EXPECT_TRUE(s.has(nav::NavSample::kPosition | nav::NavSample::kAttitude |
                      nav::NavSample::kVelocity | nav::NavSample::kTime));

    Kinematics east;  // at longitude 90°: east is −x, south is −z, down is −y
    east.location = {0, kA + 100, 0};
    east.body_to_ecef.col(0) = -Vector3d::UnitX();
    east.body_to_ecef.col(1) = -Vector3d::UnitZ();
    east.body_to_ecef.col(2) = -Vector3d::UnitY();
    east.velocity = {-10, 0, 0};
    const auto e = to_sample(east, core::GpsTime{});
    EXPECT_NEAR(e.lon_deg, 90, 1e-12);
    EXPECT_NEAR(e.height_m, 100, 1e-6);
    EXPECT_NEAR(e.heading_rad, std::numbers::pi / 2, 1e-12);
    EXPECT_NEAR(e.pitch_rad, 0, 1e-12);
    EXPECT_NEAR(e.roll_rad, 0, 1e-12);
    EXPECT_LT((e.velocity_ned_mps - Vector3d(0, 10, 0)).norm(), 1e-12);
}

// Heading 200°, pitch 10°, roll −5° over Munich (48.1°, 11.6°, 500 m): the body built from the
// written-out NED axes comes back as those angles.
TEST(DisSample, any_attitude_comes_back_as_its_ned_angles) {
    const double lat = 48.1, lon = 11.6, h = 500;
    const double n = kA / std::sqrt(1 - 0.00669437999014 * std::pow(std::sin(lat * kDeg), 2));
    Kinematics k;
    k.location = {(n + h) * std::cos(lat * kDeg) * std::cos(lon * kDeg),
                  (n + h) * std::cos(lat * kDeg) * std::sin(lon * kDeg),
                  (n * (1 - 0.00669437999014) + h) * std::sin(lat * kDeg)};
    const Matrix3d ned_body = (Eigen::AngleAxisd(200 * kDeg, Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(10 * kDeg, Vector3d::UnitY()) *
                               Eigen::AngleAxisd(-5 * kDeg, Vector3d::UnitX()))
                                  .toRotationMatrix();
    k.body_to_ecef = ecef_from_ned(lat, lon) * ned_body;
    k.velocity = ecef_from_ned(lat, lon) * Vector3d(3, -4, 1);
    const auto s = to_sample(k, core::GpsTime{});
    EXPECT_NEAR(s.lat_deg, lat, 1e-9);
    EXPECT_NEAR(s.lon_deg, lon, 1e-9);
    EXPECT_NEAR(s.height_m, h, 1e-4);
    EXPECT_NEAR(s.heading_rad, 200 * kDeg, 1e-12);
    EXPECT_NEAR(s.pitch_rad, 10 * kDeg, 1e-12);
    EXPECT_NEAR(s.roll_rad, -5 * kDeg, 1e-12);
    EXPECT_LT((s.velocity_ned_mps - Vector3d(3, -4, 1)).norm(), 1e-12);
}

TEST(DisSample, the_velocity_is_the_rate_of_the_dead_reckoned_position) {
    for (std::uint8_t alg = 1; alg <= 9; ++alg) {
        const EntityState s = moving(alg);
        const double t = 2.0, h = 1e-3;
        const Vector3d rate =
            (dead_reckon(s, t + h).location - dead_reckon(s, t - h).location) / (2 * h);
        EXPECT_LT((dead_reckon(s, t).velocity - rate).norm(), 1e-5) << int(alg);
    }
}

}  // namespace
}  // namespace mirage::dis
