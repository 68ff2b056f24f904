// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>
#include <vector>

#include "mirage/core/georef.hpp"
#include "mirage/core/pose.hpp"

namespace mirage::core {

enum class Interpolation { Linear, Cubic };

// Platform poses over time. Position: linear or cubic (Hermite; interior tangents are the
// derivative of the parabola through three neighbouring samples, which is Catmull-Rom for even
// spacing and exact for quadratic motion; end tangents are second-order one-sided differences);
// attitude: quaternion slerp along the shortest arc (never linear Euler angles, so yaw wraps
// through ±180° correctly). Outside [begin, end] the end pose is held. Thread-safe for reads.
class Trajectory {
  public:
    static Trajectory fixed(const Pose& pose);
    // Throws ConfigError ("trajectory: ...") on no samples, non-increasing times, or a zero /
    // non-finite attitude. Attitudes are normalised and flipped into one hemisphere.
    Trajectory(std::vector<StampedPose> samples, Interpolation interp = Interpolation::Linear);

    Pose at(GpsTime t) const;
    // Same as at(t); `hint` caches the segment index between calls (monotonic access is O(1)).
    Pose at(GpsTime t, std::size_t& hint) const;

    GpsTime begin() const;
    GpsTime end() const;
    bool is_fixed() const { return samples_.size() == 1; }
    const std::vector<StampedPose>& samples() const { return samples_; }
    Interpolation interpolation() const { return interp_; }

  private:
    Trajectory() = default;
    std::vector<StampedPose> samples_;
    Interpolation interp_ = Interpolation::Linear;
    std::vector<Eigen::Vector3d> tangents_;  // Cubic only: dp/dt at each sample, m/s
};

// CSV trajectory (docs/file-formats.md §3): a header row naming columns, then one row per
// sample. Time: `time` (GPS seconds, decimal, parsed exactly to ns) or `utc` (ISO 8601).
// Position: `x,y,z` (local metres), `e,n,u` (projected, minus the anchor), or `lat,lon,h`
// (WGS84 degrees / m, through the scene georeference). Attitude: `roll,pitch,yaw` in degrees
// (R = Rz(yaw)·Ry(pitch)·Rx(roll), FLU body, ENU world) or `qw,qx,qy,qz`.
// Lines starting with '#' and blank lines are skipped; names and values may be padded with
// spaces. Throws ConfigError "trajectory '<path>': line N, column '<name>': <problem>" on any
// malformed value, NaN/Inf, missing/unknown/duplicate column, non-increasing time, or no rows;
// IoError if the file cannot be read.
Trajectory load_trajectory_csv(const std::string& path, const Georef& georef,
                               Interpolation interp = Interpolation::Linear);
// The same from CSV text in memory; `name` labels errors.
Trajectory parse_trajectory_csv(const std::string& text, const std::string& name,
                                const Georef& georef, Interpolation interp = Interpolation::Linear);

// Writes the samples as `time,x,y,z,qw,qx,qy,qz` (GPS seconds with exact ns, local metres,
// shortest round-trip decimals), which load_trajectory_csv reads back bit-exactly.
// Throws IoError if the file cannot be written.
void save_trajectory_csv(const std::string& path, const Trajectory& trajectory);

}  // namespace mirage::core
