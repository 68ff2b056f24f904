// SPDX-License-Identifier: Apache-2.0
// DIS state -> NavSample (docs/dis.md §4).
#include "mirage/dis/dis_sample.hpp"

#include <GeographicLib/Geocentric.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "mirage/core/pose.hpp"

namespace mirage::dis {

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
    Eigen::Matrix3d enu_to_ecef;
    enu_to_ecef << m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8];
    Eigen::Matrix3d ned_from_enu;
    ned_from_enu << 0, 1, 0, 1, 0, 0, 0, 0, -1;
    const Eigen::Matrix3d ned_from_ecef = ned_from_enu * enu_to_ecef.transpose();
    s.velocity_ned_mps = ned_from_ecef * k.velocity;
    const Eigen::Vector3d rpy =
        core::rpy_from_quaternion(Eigen::Quaterniond(ned_from_ecef * k.body_to_ecef));
    s.roll_rad = rpy.x();
    s.pitch_rad = rpy.y();
    s.heading_rad = rpy.z() < 0 ? rpy.z() + 2 * std::numbers::pi : rpy.z();
    if (s.heading_rad >= 2 * std::numbers::pi) s.heading_rad = 0;
    return s;
}

}  // namespace mirage::dis
