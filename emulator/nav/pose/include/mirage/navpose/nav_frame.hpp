// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Geometry>

#include "mirage/core/georef.hpp"
#include "mirage/core/pose.hpp"
#include "mirage/nav/nav_sample.hpp"

namespace mirage::navpose {

// Maps navigation solutions (WGS84, NED attitude of an FRD body, true north) to the scene's
// local frame (grid east/north/up relative to the anchor, FLU body) and back, for every message
// of a live run: GeographicLib's UTM/UPS, not PROJ, because it costs microseconds per call and
// returns the meridian convergence γ that turns true headings into grid headings.
class NavFrame {
  public:
    // Scenes georeferenced in UTM (EPSG 326zz / 327zz) or UPS (32661 / 32761). Throws
    // ConfigError "nav frame: EPSG:<n> ..." for other CRSs or a scene without one.
    static NavFrame from_georef(const core::Georef& georef);
    // A local tangent plane (true ENU) at a geodetic origin, for scenes without a georeference.
    static NavFrame tangent_plane(double lat_deg, double lon_deg, double h_m);

    // Local position of a WGS84 point (ellipsoidal height).
    Eigen::Vector3d local_from_geodetic(double lat_deg, double lon_deg, double h_m) const;
    // (lat_deg, lon_deg, h_m) of a local position.
    Eigen::Vector3d geodetic_from_local(const Eigen::Vector3d& local) const;
    // Meridian convergence at a point: bearing of grid north clockwise from true north, rad.
    double convergence_rad(double lat_deg, double lon_deg) const;

    // Body attitude in the local frame (FLU into grid ENU) from NED Euler angles at a point.
    Eigen::Quaterniond local_attitude(double roll_rad, double pitch_rad, double heading_rad,
                                      double lat_deg, double lon_deg) const;
    // Inverse: NED Euler angles (roll, pitch, heading in [0, 2π)) of a local attitude.
    Eigen::Vector3d ned_euler(const Eigen::Quaterniond& local_attitude, double lat_deg,
                              double lon_deg) const;
    // NED velocity -> local ENU (grid) velocity at a point, and back.
    Eigen::Vector3d local_velocity(const Eigen::Vector3d& ned, double lat_deg,
                                   double lon_deg) const;
    Eigen::Vector3d ned_velocity(const Eigen::Vector3d& local, double lat_deg,
                                 double lon_deg) const;

    // A NavSample's pose in the local frame (position and attitude must be present).
    core::Pose pose(const nav::NavSample& s) const;
    // The NavSample a perfect INS at `pose` would report (position, attitude, velocity given in
    // the local frame), for the fake INS: fields kPosition | kAttitude | kVelocity.
    nav::NavSample sample(const core::Pose& pose, const Eigen::Vector3d& local_velocity) const;

  private:
    enum class Kind { Utm, Tangent };
    Kind kind_ = Kind::Utm;
    int zone_ = 0;  // UTM zone 1..60, 0 = UPS
    bool north_ = true;
    Eigen::Vector3d anchor_{Eigen::Vector3d::Zero()};  // projected anchor (UTM) / unused
    double lat0_ = 0, lon0_ = 0, h0_ = 0;              // tangent-plane origin
};

}  // namespace mirage::navpose
