// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/trajectory.hpp"

#include <algorithm>
#include <cmath>

#include "mirage/core/error.hpp"

namespace mirage::core {
namespace {

double seconds(Nanos d) { return static_cast<double>(d.count()) * 1e-9; }

}  // namespace

Trajectory Trajectory::fixed(const Pose& pose) {
    return Trajectory(std::vector<StampedPose>{{GpsTime{}, pose}});
}

Trajectory::Trajectory(std::vector<StampedPose> samples, Interpolation interp)
    : samples_(std::move(samples)), interp_(interp) {
    if (samples_.empty()) throw ConfigError("trajectory: no samples");
    for (std::size_t i = 0; i < samples_.size(); ++i) {
        auto& s = samples_[i];
        if (i > 0 && s.t <= samples_[i - 1].t) {
            throw ConfigError("trajectory: sample " + std::to_string(i) + ": time " +
                              format_decimal_seconds(s.t.time_since_epoch()) +
                              " s is not after the previous sample's " +
                              format_decimal_seconds(samples_[i - 1].t.time_since_epoch()));
        }
        if (!s.pose.position.allFinite()) {
            throw ConfigError("trajectory: sample " + std::to_string(i) + ": position not finite");
        }
        auto& q = s.pose.attitude;
        const double n2 = q.squaredNorm();
        if (!std::isfinite(n2) || n2 < 1e-24) {
            throw ConfigError("trajectory: sample " + std::to_string(i) +
                              ": attitude quaternion is zero or not finite");
        }
        // Leave unit quaternions bit-identical (so a saved trajectory reloads exactly).
        if (std::abs(n2 - 1.0) > 4e-16) q.normalize();
        // Same hemisphere as the previous sample: q and −q are one rotation, and slerp between
        // neighbours must take the short arc.
        if (i > 0 && q.dot(samples_[i - 1].pose.attitude) < 0.0) q.coeffs() = -q.coeffs();
    }

    if (interp_ == Interpolation::Cubic && samples_.size() > 1) {
        const std::size_t n = samples_.size();
        std::vector<Eigen::Vector3d> slope(n - 1);  // chord velocities, m/s
        std::vector<double> h(n - 1);               // segment durations, s
        for (std::size_t i = 0; i + 1 < n; ++i) {
            h[i] = seconds(samples_[i + 1].t - samples_[i].t);
            slope[i] = (samples_[i + 1].pose.position - samples_[i].pose.position) / h[i];
        }
        tangents_.resize(n);
        // Interior: derivative of the parabola through samples i−1, i, i+1, i.e. the chord
        // slopes weighted by the opposite segment's duration (Catmull-Rom for even spacing).
        for (std::size_t i = 1; i + 1 < n; ++i) {
            tangents_[i] = (h[i] * slope[i - 1] + h[i - 1] * slope[i]) / (h[i - 1] + h[i]);
        }
        if (n == 2) {
            tangents_[0] = tangents_[1] = slope[0];  // a single segment stays a straight line
        } else {
            // Ends: second-order one-sided difference, the parabola's end slope
            // (its chord slope is the mean of its two end slopes). A first-order end tangent
            // (the chord alone) makes the end segments worse than linear on curved paths.
            tangents_.front() = 2.0 * slope.front() - tangents_[1];
            tangents_.back() = 2.0 * slope.back() - tangents_[n - 2];
        }
    }
}

GpsTime Trajectory::begin() const { return samples_.front().t; }
GpsTime Trajectory::end() const { return samples_.back().t; }

Pose Trajectory::at(GpsTime t) const {
    std::size_t hint = 0;
    return at(t, hint);
}

Pose Trajectory::at(GpsTime t, std::size_t& hint) const {
    const std::size_t n = samples_.size();
    if (n == 1 || t <= samples_.front().t) {
        hint = 0;
        return samples_.front().pose;
    }
    if (t >= samples_.back().t) {
        hint = n - 2;
        return samples_.back().pose;
    }
    // Here t0 < t < tn, so a segment i with t_i <= t < t_{i+1} exists.
    std::size_t i = hint;
    const auto in_segment = [&](std::size_t k) {
        return k < n - 1 && samples_[k].t <= t && t < samples_[k + 1].t;
    };
    if (!in_segment(i)) {
        if (in_segment(i + 1)) {
            ++i;  // monotonic access moving into the next segment
        } else {
            auto it = std::upper_bound(samples_.begin(), samples_.end(), t,
                                       [](GpsTime v, const StampedPose& s) { return v < s.t; });
            i = static_cast<std::size_t>(it - samples_.begin()) - 1;
        }
    }
    hint = i;

    const StampedPose& a = samples_[i];
    const StampedPose& b = samples_[i + 1];
    // Fraction from integer ns; only the ratio becomes a double.
    const double u =
        static_cast<double>((t - a.t).count()) / static_cast<double>((b.t - a.t).count());

    Pose out;
    if (interp_ == Interpolation::Cubic) {
        const double h = seconds(b.t - a.t);
        const double u2 = u * u, u3 = u2 * u;
        const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u;
        const double h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
        out.position = h00 * a.pose.position + (h10 * h) * tangents_[i] + h01 * b.pose.position +
                       (h11 * h) * tangents_[i + 1];
    } else {
        // (1−u)·a + u·b is exact at both ends and at u = ½.
        out.position = (1.0 - u) * a.pose.position + u * b.pose.position;
    }
    out.attitude = a.pose.attitude.slerp(u, b.pose.attitude);
    return out;
}

}  // namespace mirage::core
