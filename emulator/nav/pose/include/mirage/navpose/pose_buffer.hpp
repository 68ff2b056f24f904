// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

#include "mirage/core/pose.hpp"
#include "mirage/core/time.hpp"
#include "mirage/core/trajectory.hpp"

namespace mirage::navpose {

struct PoseBufferConfig {
    core::Nanos max_extrapolation{std::chrono::milliseconds(50)};
    // A position further than this from the one predicted from the previous samples (constant
    // velocity) is a jump: rejected, never applied.
    double max_jump_m = 20.0;
    // A sample older than the newest by more than this is dropped (history kept for
    // interpolation).
    core::Nanos history{std::chrono::seconds(2)};
};

enum class AddStatus : std::uint8_t {
    Accepted,
    NotFinite,      // NaN / Inf in position or attitude
    Duplicate,      // same time as the newest sample of its track (another log of the same
                    // epoch): ignored, not an error
    TimeBackwards,  // older than the newest sample of its track
    PositionJump,   // beyond max_jump_m of the prediction
};

enum class PoseStatus : std::uint8_t {
    Interpolated,  // bracketed by two samples (slerp / linear)
    Extrapolated,  // after the newest sample, within max_extrapolation
    Stale,         // no pose: beyond max_extrapolation, or before the first sample
    Empty,         // nothing received yet
};

struct PoseBufferCounters {
    std::uint64_t accepted = 0;
    std::uint64_t not_finite = 0;
    std::uint64_t duplicates = 0;
    std::uint64_t time_backwards = 0;
    std::uint64_t position_jumps = 0;
};

// Platform poses as an INS reports them, queried at each firing time. Position and attitude are
// separate tracks with their own timestamps, because some protocols send them in different
// messages at different rates (NMEA: GGA at 10 Hz, PASHR at 25 Hz). Positions interpolate
// linearly and extrapolate with the last velocity (from the samples, or as given); attitudes
// slerp and hold beyond the newest. Thread-safe: one writer (the nav thread), many readers.
class PoseBuffer {
  public:
    explicit PoseBuffer(PoseBufferConfig config = {});

    AddStatus add_position(core::GpsTime t, const Eigen::Vector3d& local,
                           const std::optional<Eigen::Vector3d>& velocity = std::nullopt);
    AddStatus add_attitude(core::GpsTime t, const Eigen::Quaterniond& attitude);

    struct Query {
        PoseStatus status = PoseStatus::Empty;
        core::Pose pose;
        core::Nanos age{0};  // t − the older of the two tracks' newest samples
    };
    Query at(core::GpsTime t) const;

    // Poses every `step` over [t0, t1] (both ends included) as a Trajectory for the renderer,
    // or nullopt if any of them is stale. The renderer's per-pulse interpolation between these
    // knots then matches at() within the step's curvature.
    std::optional<core::Trajectory> window(core::GpsTime t0, core::GpsTime t1,
                                           core::Nanos step) const;

    // Newest time present in both tracks (nullopt before the first full pose).
    std::optional<core::GpsTime> newest() const;
    PoseBufferCounters counters() const;

  private:
    struct PosSample {
        core::GpsTime t;
        Eigen::Vector3d p;
        std::optional<Eigen::Vector3d> v;
    };
    struct AttSample {
        core::GpsTime t;
        Eigen::Quaterniond q;
    };
    Query at_locked(core::GpsTime t) const;
    Eigen::Vector3d velocity_at_end() const;

    PoseBufferConfig cfg_;
    mutable std::mutex mu_;
    std::deque<PosSample> pos_;
    std::deque<AttSample> att_;
    PoseBufferCounters counters_;
    int consecutive_jumps_ = 0;
};

}  // namespace mirage::navpose
