// SPDX-License-Identifier: Apache-2.0
// Closed-form truth for the PCL tests: a closed box room around the sensor (every ray hits), the
// distance of a PCL point to the room's planes, and the expected points per revolution.
#pragma once
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "mirage/velodyne/model.hpp"

namespace mirage::test {

// Inside of a 20 × 16 × 6 m box, floor at z = 0: walls x = ±10, y = ±8, ceiling z = 6.
struct Room {
    double half_x = 10, half_y = 8, height = 6;

    std::string yaml() const {
        return "description: closed room around the sensor (PCL client tests)\n"
               "materials:\n"
               "  wall: {reflectance: 0.5}\n"
               "objects:\n"
               "  - type: box\n"
               "    material: wall\n"
               "    size: [" +
               std::to_string(2 * half_x) + ", " + std::to_string(2 * half_y) + ", " +
               std::to_string(height) + "]\n    transform: {translate: [0, 0, " +
               std::to_string(height / 2) + "]}\n";
    }
    void write(const std::string& path) const { std::ofstream(path) << yaml(); }
    // Distance from a world point inside the room to the nearest of its six planes.
    double distance(const Eigen::Vector3d& w) const {
        return std::min({std::abs(w.x() - half_x), std::abs(w.x() + half_x),
                         std::abs(w.y() - half_y), std::abs(w.y() + half_y), std::abs(w.z()),
                         std::abs(w.z() - height)});
    }
};

// The emulated sensor: static pose (yaw only) and rotation rate.
struct SensorSetup {
    velodyne::Model model = velodyne::Model::Vlp16;
    Eigen::Vector3d position{2.0, -1.0, 1.5};
    double yaw_deg = 30;
    double rpm = 600;
    // Points PCL makes per laser firing: 1, or 2 when HDLGrabber reads a dual-return stream (it
    // has no dual logic and decodes both blocks of a pair as separate firings).
    int points_per_firing = 1;

    std::string pose_arg() const {
        return std::to_string(position.x()) + "," + std::to_string(position.y()) + "," +
               std::to_string(position.z()) + ",0,0," + std::to_string(yaw_deg);
    }
    const velodyne::ModelDescriptor& descriptor() const { return velodyne::descriptor(model); }
    // Firing sequences per revolution: 60 s / (rpm · sequence period).
    double sequences_per_rev() const {
        return 60e9 / (rpm * static_cast<double>(descriptor().sequence_period_ns));
    }
};

// How one sweep (or all) compares with the room.
struct GeometryStats {
    std::size_t points = 0;
    std::size_t outside_tolerance = 0;  // distance > per-point tolerance
    double worst_m = 0;                 // after undoing PCL's azimuth simplification
    double worst_ratio = 0;             // worst distance / its tolerance
    double worst_raw_m = 0;             // PCL's point exactly as decoded
    double rms_m = 0;
    double worst_elevation_mismatch_deg = 0;  // PCL's elevation vs the nearest Mirage laser

    void merge(const GeometryStats& o) {
        const double ss = rms_m * rms_m * static_cast<double>(points) +
                          o.rms_m * o.rms_m * static_cast<double>(o.points);
        points += o.points;
        outside_tolerance += o.outside_tolerance;
        worst_m = std::max(worst_m, o.worst_m);
        worst_ratio = std::max(worst_ratio, o.worst_ratio);
        worst_raw_m = std::max(worst_raw_m, o.worst_raw_m);
        worst_elevation_mismatch_deg =
            std::max(worst_elevation_mismatch_deg, o.worst_elevation_mismatch_deg);
        rms_m = points ? std::sqrt(ss / static_cast<double>(points)) : 0.0;
    }
};

// Checks PCL points against the room.
//
// PCL's frame is the manual's (x right, y forward, z up; azimuth α clockwise from +y):
// x = r·sin α, y = r·cos α. Mirage's sensor frame is FLU with azimuth clockwise from +x, so
// (x, y, z)_FLU = (y, −x, z)_PCL — the same swap ROS applies (docs/wire-formats.md §1.8).
//
// PCL's azimuth: HDLGrabber gives every slot of a block the block azimuth; VLPGrabber gives
// slots 16–31 the block azimuth + half the packet's first block step and slots 0–15 the block
// azimuth. Neither adds the laser's firing delay within its sequence (up to 34.56 µs on the
// VLP-16: 0.124° at 600 rpm), so a raw point is rotated back by up to that angle. The check
// adds the delay of the laser (identified by its elevation) back: α = α_PCL + 360°·f·t_fire.
// What remains is the 0.01° wire rounding of the block azimuth (PCL's VLP interpolation adds
// a truncated half step): `azimuth_tol_deg`.
//
// Per-point tolerance: half the 2 mm range LSB + r_h·azimuth_tol + float rounding, plus
// `extra_m` (e.g. 5σ of range noise).
class RoomChecker {
  public:
    RoomChecker(const Room& room, const SensorSetup& setup, double azimuth_tol_deg, double extra_m)
        : room_(room),
          setup_(setup),
          az_tol_rad_(azimuth_tol_deg * std::numbers::pi / 180.0),
          extra_m_(extra_m),
          attitude_(Eigen::AngleAxisd(setup.yaw_deg * std::numbers::pi / 180.0,
                                      Eigen::Vector3d::UnitZ())) {}

    GeometryStats check(const pcl::PointCloud<pcl::PointXYZI>& cloud) const {
        const auto& d = setup_.descriptor();
        const double deg_per_ns = 360.0 * setup_.rpm / 60.0 * 1e-9;
        GeometryStats s;
        double ss = 0;
        for (const auto& p : cloud.points) {
            const double x = p.x, y = p.y, z = p.z;
            const double rh = std::hypot(x, y);
            const double el_deg = std::atan2(z, rh) * 180.0 / std::numbers::pi;
            std::size_t laser = 0;
            double best = 1e9;
            for (std::size_t l = 0; l < d.laser.size(); ++l) {
                const double e = std::abs(d.laser[l].elevation_deg - el_deg);
                if (e < best) {
                    best = e;
                    laser = l;
                }
            }
            s.worst_elevation_mismatch_deg = std::max(s.worst_elevation_mismatch_deg, best);
            const double alpha_pcl = std::atan2(x, y);
            const double delay_rad = deg_per_ns *
                                     static_cast<double>(d.laser[laser].firing_offset_ns) *
                                     std::numbers::pi / 180.0;
            const double raw = distance_at(alpha_pcl, rh, z);
            const double dist = distance_at(alpha_pcl + delay_rad, rh, z);
            const double range = std::sqrt(rh * rh + z * z);
            const double tol = 0.001 + rh * az_tol_rad_ + 2e-6 * range + 1e-5 + extra_m_;
            ++s.points;
            ss += dist * dist;
            if (dist > tol) ++s.outside_tolerance;
            s.worst_m = std::max(s.worst_m, dist);
            s.worst_ratio = std::max(s.worst_ratio, dist / tol);
            s.worst_raw_m = std::max(s.worst_raw_m, raw);
        }
        s.rms_m = s.points ? std::sqrt(ss / static_cast<double>(s.points)) : 0.0;
        return s;
    }

  private:
    // PCL-frame azimuth α (clockwise from forward), horizontal range and height → distance of
    // the world point to the room.
    double distance_at(double alpha, double rh, double z) const {
        const Eigen::Vector3d flu(rh * std::cos(alpha), -rh * std::sin(alpha), z);
        return room_.distance(setup_.position + attitude_ * flu);
    }

    Room room_;
    SensorSetup setup_;
    double az_tol_rad_;
    double extra_m_;
    Eigen::Matrix3d attitude_;
};

}  // namespace mirage::test
