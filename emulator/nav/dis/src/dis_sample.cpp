// SPDX-License-Identifier: Apache-2.0
// DIS state -> NavSample (docs/dis.md §4).
#include "mirage/dis/dis_sample.hpp"

#include <GeographicLib/Geocentric.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "mirage/core/pose.hpp"

namespace mirage::dis {
namespace {

// North-east-down from east-north-up (its own inverse).
Eigen::Matrix3d ned_from_enu() {
    Eigen::Matrix3d m;
    m << 0, 1, 0, 1, 0, 0, 0, 0, -1;
    return m;
}

// GeographicLib's rotation matrix (local east-north-up into ECEF at the point).
Eigen::Matrix3d enu_to_ecef(const std::vector<double>& m) {
    Eigen::Matrix3d r;
    r << m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8];
    return r;
}

}  // namespace

nav::NavSample to_sample(const Kinematics& k, core::GpsTime t) {
    nav::NavSample s;
    s.source = nav::Protocol::Dis;
    s.fields = nav::NavSample::kTime | nav::NavSample::kPosition | nav::NavSample::kAttitude |
               nav::NavSample::kVelocity;
    s.quality = nav::FixQuality::Simulated;
    s.t = t;
    // M turns local east-north-up into ECEF at the point (GeographicLib's convention).
    std::vector<double> m(9, 0.0);
    GeographicLib::Geocentric::WGS84().Reverse(k.location.x(), k.location.y(), k.location.z(),
                                               s.lat_deg, s.lon_deg, s.height_m, m);
    const Eigen::Matrix3d ned_from_ecef = ned_from_enu() * enu_to_ecef(m).transpose();
    s.velocity_ned_mps = ned_from_ecef * k.velocity;
    const Eigen::Vector3d rpy =
        core::rpy_from_quaternion(Eigen::Quaterniond(ned_from_ecef * k.body_to_ecef));
    s.roll_rad = rpy.x();
    s.pitch_rad = rpy.y();
    s.heading_rad = rpy.z() < 0 ? rpy.z() + 2 * std::numbers::pi : rpy.z();
    if (s.heading_rad >= 2 * std::numbers::pi) s.heading_rad = 0;
    return s;
}

EntityState from_sample(const nav::NavSample& s, const EntityId& id, std::uint8_t exercise) {
    EntityState e;
    e.exercise = exercise;
    e.id = id;
    std::vector<double> m(9, 0.0);
    GeographicLib::Geocentric::WGS84().Forward(s.lat_deg, s.lon_deg, s.height_m, e.location.x(),
                                               e.location.y(), e.location.z(), m);
    const Eigen::Matrix3d ecef_from_ned = enu_to_ecef(m) * ned_from_enu();
    const Eigen::Matrix3d body =
        ecef_from_ned *
        core::quaternion_from_rpy(s.roll_rad, s.pitch_rad, s.heading_rad).toRotationMatrix();
    const Eigen::Vector3d psi_theta_phi = euler_of(body);
    e.psi = static_cast<float>(psi_theta_phi.x());
    e.theta = static_cast<float>(psi_theta_phi.y());
    e.phi = static_cast<float>(psi_theta_phi.z());
    const Eigen::Vector3d v = ecef_from_ned * s.velocity_ned_mps;
    const bool rates = s.has(nav::NavSample::kAngularRate);
    e.dr_algorithm = rates ? 7 : 2;  // RPB: a vehicle's velocity turns with it
    e.velocity = (rates ? Eigen::Vector3d(body.transpose() * v) : v).cast<float>();
    if (rates) e.dr_angular_velocity = s.rate_frd_radps.cast<float>();
    e.timestamp = encode_timestamp(utc_seconds_past_hour(s.t), true);
    return e;
}

}  // namespace mirage::dis
