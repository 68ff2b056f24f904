// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>

#include "mirage/core/time.hpp"

namespace mirage::nav {

// Which protocol produced a sample.
enum class Protocol : std::uint8_t { Nmea, Novatel, Ncom, OxtsCan, SbgCan, Dis };

// Fix quality mapped from each protocol's own enum.
enum class FixQuality : std::uint8_t {
    Unknown,
    None,
    Autonomous,
    Differential,
    RtkFloat,
    RtkFixed,
    DeadReckoning,
    Simulated,
};

// A navigation solution as one message (or one group of frames) reports it, in the
// protocol-neutral form every codec produces and every encoder consumes. Conventions are fixed
// here so each codec maps its own explicitly (docs/nav-protocols.md §0):
//  - time: GPS time scale, integer ns since the GPS epoch (UTC sources converted with the
//    leap-second table of mirage::core);
//  - position: WGS84 latitude/longitude in degrees, height above the ellipsoid in metres
//    (codecs add the undulation when the message gives MSL + undulation; when a protocol gives
//    MSL only, the field bit kHeightIsMsl says so);
//  - velocity: north, east, down in m/s;
//  - attitude: aerospace NED Euler angles in radians, body FRD: R_ned_body =
//    Rz(heading)·Ry(pitch)·Rx(roll); heading clockwise from true north in [0, 2π), pitch
//    nose-up positive, roll right-side-down positive;
//  - acceleration and angular rate: body FRD, m/s² and rad/s.
struct NavSample {
    enum Field : std::uint32_t {
        kTime = 1u << 0,          // t is the full GPS time of validity
        kPosition = 1u << 1,      // lat/lon/height
        kVelocity = 1u << 2,      // velocity_ned_mps
        kAttitude = 1u << 3,      // roll, pitch and heading
        kHeading = 1u << 4,       // heading only (e.g. $..HDT); roll/pitch not valid
        kAcceleration = 1u << 5,  // accel_frd_mps2
        kAngularRate = 1u << 6,   // rate_frd_radps
        kHeightIsMsl = 1u << 7,   // height_m is above mean sea level, not the ellipsoid
    };

    Protocol source = Protocol::Nmea;
    std::uint32_t fields = 0;
    core::GpsTime t{};

    double lat_deg = 0.0;
    double lon_deg = 0.0;
    double height_m = 0.0;

    Eigen::Vector3d velocity_ned_mps{Eigen::Vector3d::Zero()};

    double roll_rad = 0.0;
    double pitch_rad = 0.0;
    double heading_rad = 0.0;

    Eigen::Vector3d accel_frd_mps2{Eigen::Vector3d::Zero()};
    Eigen::Vector3d rate_frd_radps{Eigen::Vector3d::Zero()};

    FixQuality quality = FixQuality::Unknown;
    std::uint8_t satellites = 0;

    bool has(std::uint32_t mask) const { return (fields & mask) == mask; }
};

using SampleFn = std::function<void(const NavSample&)>;

}  // namespace mirage::nav
