// SPDX-License-Identifier: Apache-2.0
#include "mirage/navpose/nav_frame.hpp"

#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/UTMUPS.hpp>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "mirage/core/error.hpp"

namespace mirage::navpose {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kFalseNorthingSouth = 10'000'000.0;

// NED -> ENU axes, and FLU -> FRD body axes (each its own inverse).
const Eigen::Matrix3d& ned_to_enu() {
    static const Eigen::Matrix3d m = (Eigen::Matrix3d() << 0, 1, 0, 1, 0, 0, 0, 0, -1).finished();
    return m;
}
const Eigen::Matrix3d& flu_to_frd() {
    static const Eigen::Matrix3d m = Eigen::Vector3d(1, -1, -1).asDiagonal();
    return m;
}

double wrap_two_pi(double a) {
    a = std::fmod(a, 2.0 * std::numbers::pi);
    if (a < 0) a += 2.0 * std::numbers::pi;
    return a;
}

}  // namespace

NavFrame NavFrame::from_georef(const core::Georef& georef) {
    const int epsg = georef.epsg();
    NavFrame f;
    f.kind_ = Kind::Utm;
    f.anchor_ = georef.anchor();
    if (epsg >= 32601 && epsg <= 32660) {
        f.zone_ = epsg - 32600;
        f.north_ = true;
    } else if (epsg >= 32701 && epsg <= 32760) {
        f.zone_ = epsg - 32700;
        f.north_ = false;
    } else if (epsg == 32661 || epsg == 32761) {
        f.zone_ = GeographicLib::UTMUPS::UPS;
        f.north_ = epsg == 32661;
    } else {
        throw ConfigError(
            "nav frame: EPSG:" + std::to_string(epsg) +
            (epsg == 0 ? " (the scene has no georeference)" : "") +
            ": INS input needs a scene georeferenced in WGS84 UTM/UPS (EPSG 326zz, 327zz, 32661, "
            "32761), or a tangent-plane origin (--nav-origin lat,lon,h)");
    }
    return f;
}

NavFrame NavFrame::tangent_plane(double lat_deg, double lon_deg, double h_m) {
    if (!std::isfinite(lat_deg) || !std::isfinite(lon_deg) || !std::isfinite(h_m) ||
        std::abs(lat_deg) > 90.0 || std::abs(lon_deg) > 180.0)
        throw ConfigError("nav frame: tangent-plane origin out of range");
    NavFrame f;
    f.kind_ = Kind::Tangent;
    f.lat0_ = lat_deg;
    f.lon0_ = lon_deg;
    f.h0_ = h_m;
    return f;
}

Eigen::Vector3d NavFrame::local_from_geodetic(double lat_deg, double lon_deg, double h_m) const {
    if (kind_ == Kind::Tangent) {
        const GeographicLib::LocalCartesian lc(lat0_, lon0_, h0_);
        double x = 0, y = 0, z = 0;
        lc.Forward(lat_deg, lon_deg, h_m, x, y, z);
        return {x, y, z};
    }
    int zone = 0;
    bool northp = true;
    double x = 0, y = 0, gamma = 0, k = 0;
    GeographicLib::UTMUPS::Forward(lat_deg, lon_deg, zone, northp, x, y, gamma, k, zone_);
    // Across the equator GeographicLib switches the false northing; the scene keeps its own.
    if (zone_ != GeographicLib::UTMUPS::UPS && northp != north_)
        y += north_ ? -kFalseNorthingSouth : kFalseNorthingSouth;
    return Eigen::Vector3d(x, y, h_m) - anchor_;
}

Eigen::Vector3d NavFrame::geodetic_from_local(const Eigen::Vector3d& local) const {
    if (kind_ == Kind::Tangent) {
        const GeographicLib::LocalCartesian lc(lat0_, lon0_, h0_);
        double lat = 0, lon = 0, h = 0;
        lc.Reverse(local.x(), local.y(), local.z(), lat, lon, h);
        return {lat, lon, h};
    }
    const Eigen::Vector3d w = local + anchor_;
    double lat = 0, lon = 0;
    GeographicLib::UTMUPS::Reverse(zone_, north_, w.x(), w.y(), lat, lon);
    return {lat, lon, w.z()};
}

double NavFrame::convergence_rad(double lat_deg, double lon_deg) const {
    if (kind_ == Kind::Tangent) return 0.0;
    int zone = 0;
    bool northp = true;
    double x = 0, y = 0, gamma = 0, k = 0;
    GeographicLib::UTMUPS::Forward(lat_deg, lon_deg, zone, northp, x, y, gamma, k, zone_);
    return gamma * kDeg;
}

// Grid ENU from true ENU: a true bearing β is the grid bearing β − γ, a rotation by +γ about up.
Eigen::Quaterniond NavFrame::local_attitude(double roll_rad, double pitch_rad,
                                            double heading_rad, double lat_deg,
                                            double lon_deg) const {
    const Eigen::Matrix3d r_ned_frd =
        (Eigen::AngleAxisd(heading_rad, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    const Eigen::Matrix3d grid =
        Eigen::AngleAxisd(convergence_rad(lat_deg, lon_deg), Eigen::Vector3d::UnitZ())
            .toRotationMatrix();
    Eigen::Quaterniond q(grid * ned_to_enu() * r_ned_frd * flu_to_frd());
    return q.normalized();
}

Eigen::Vector3d NavFrame::ned_euler(const Eigen::Quaterniond& local_attitude, double lat_deg,
                                    double lon_deg) const {
    const Eigen::Matrix3d grid_inv =
        Eigen::AngleAxisd(-convergence_rad(lat_deg, lon_deg), Eigen::Vector3d::UnitZ())
            .toRotationMatrix();
    const Eigen::Matrix3d r =
        ned_to_enu() * grid_inv * local_attitude.toRotationMatrix() * flu_to_frd();
    const double pitch = -std::asin(std::clamp(r(2, 0), -1.0, 1.0));
    const double roll = std::atan2(r(2, 1), r(2, 2));
    const double heading = wrap_two_pi(std::atan2(r(1, 0), r(0, 0)));
    return {roll, pitch, heading};
}

Eigen::Vector3d NavFrame::local_velocity(const Eigen::Vector3d& ned, double lat_deg,
                                         double lon_deg) const {
    return Eigen::AngleAxisd(convergence_rad(lat_deg, lon_deg), Eigen::Vector3d::UnitZ()) *
           (ned_to_enu() * ned);
}

Eigen::Vector3d NavFrame::ned_velocity(const Eigen::Vector3d& local, double lat_deg,
                                       double lon_deg) const {
    return ned_to_enu() *
           (Eigen::AngleAxisd(-convergence_rad(lat_deg, lon_deg), Eigen::Vector3d::UnitZ()) *
            local);
}

core::Pose NavFrame::pose(const nav::NavSample& s) const {
    core::Pose p;
    p.position = local_from_geodetic(s.lat_deg, s.lon_deg, s.height_m);
    p.attitude = local_attitude(s.roll_rad, s.pitch_rad, s.heading_rad, s.lat_deg, s.lon_deg);
    return p;
}

nav::NavSample NavFrame::sample(const core::Pose& pose,
                                const Eigen::Vector3d& local_velocity) const {
    nav::NavSample s;
    const Eigen::Vector3d g = geodetic_from_local(pose.position);
    s.lat_deg = g.x();
    s.lon_deg = g.y();
    s.height_m = g.z();
    const Eigen::Vector3d e = ned_euler(pose.attitude, s.lat_deg, s.lon_deg);
    s.roll_rad = e.x();
    s.pitch_rad = e.y();
    s.heading_rad = e.z();
    s.velocity_ned_mps = ned_velocity(local_velocity, s.lat_deg, s.lon_deg);
    s.fields = nav::NavSample::kPosition | nav::NavSample::kAttitude | nav::NavSample::kVelocity;
    return s;
}

}  // namespace mirage::navpose
