// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>
#include <vector>

#include "mirage/core/georef.hpp"
#include "mirage/core/pose.hpp"

namespace mirage::core {

enum class Interpolation { Linear, Cubic };

// Platform poses over time. Position: linear or cubic (Catmull-Rom / Hermite on the samples);
// attitude: quaternion slerp along the shortest arc (never linear Euler angles, so yaw wraps
// through ±180° correctly). Outside [begin, end] the end pose is held. Thread-safe for reads.
class Trajectory {
public:
    static Trajectory fixed(const Pose& pose);
    Trajectory(std::vector<StampedPose> samples, Interpolation interp = Interpolation::Linear);

    Pose at(GpsTime t) const;
    // Same as at(t); `hint` caches the segment index between calls (monotonic access is O(1)).
    Pose at(GpsTime t, std::size_t& hint) const;

    GpsTime begin() const;
    GpsTime end() const;
    bool is_fixed() const { return samples_.size() == 1; }
    const std::vector<StampedPose>& samples() const { return samples_; }

private:
    Trajectory() = default;
    std::vector<StampedPose> samples_;
    Interpolation interp_ = Interpolation::Linear;
};

// CSV trajectory (see README "Trajectory CSV"): a header row naming columns, then one row per
// sample. Time: `time` (GPS seconds, decimal, parsed exactly to ns) or `utc` (ISO 8601).
// Position: `x,y,z` (local metres), `e,n,u` (projected, minus the anchor), or `lat,lon,h`
// (WGS84 degrees / m, through the scene georeference). Attitude: `roll,pitch,yaw` in degrees
// (R = Rz(yaw)·Ry(pitch)·Rx(roll), FLU body, ENU world) or `qw,qx,qy,qz`.
// Throws ConfigError naming the file, line and column on any malformed value, NaN, or
// non-increasing time.
Trajectory load_trajectory_csv(const std::string& path, const Georef& georef,
                               Interpolation interp = Interpolation::Linear);

}  // namespace mirage::core
