// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <vector>

#include "mirage/core/pose.hpp"
#include "mirage/core/time.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/navpose/track_update.hpp"

namespace mirage::navpose {

struct PoseBufferConfig {
    core::Nanos max_extrapolation{std::chrono::milliseconds(50)};
    // A sample older than the newest by more than this is dropped (history kept for
    // interpolation).
    core::Nanos history{std::chrono::seconds(2)};
};

enum class PoseStatus : std::uint8_t {
    Interpolated,  // bracketed by two samples (slerp / linear)
    Extrapolated,  // after the newest sample, within max_extrapolation
    Stale,         // no pose: beyond max_extrapolation, or before the first sample
    Empty,         // nothing received yet
};

// A message whose sample a pose was computed from: interpolation uses both bracketing samples,
// extrapolation the newest.
struct UsedMessage {
    MessageTag tag;
    Track track = Track::Position;
    friend bool operator==(const UsedMessage& a, const UsedMessage& b) {
        return a.tag.seq == b.tag.seq && a.track == b.track;
    }
};

// Poses over a window for the renderer, and the messages they came from.
struct PoseWindow {
    core::Trajectory trajectory;
    std::vector<UsedMessage> used;  // each message once per track, in no particular order
};

// Platform poses as an INS reports them, queried at each firing time. Position and attitude are
// separate tracks with their own timestamps, because some protocols send them in different
// messages at different rates (NMEA: GGA at 10 Hz, PASHR at 25 Hz). Positions interpolate
// linearly and extrapolate with the last velocity (from the samples, or as given); attitudes
// slerp and continue the last rotation rate beyond the newest. Stores the updates NavMapper
// accepted (it applies the rejection rules); an update not newer than its track's newest is
// ignored. Thread-safe: one writer (the nav thread), many readers.
class PoseBuffer {
  public:
    explicit PoseBuffer(PoseBufferConfig config = {});

    void add(const PositionUpdate& u);
    void add(const AttitudeUpdate& u);

    struct Query {
        PoseStatus status = PoseStatus::Empty;
        core::Pose pose;
        core::Nanos age{0};  // t − the older of the two tracks' newest samples
    };
    Query at(core::GpsTime t) const;

    // Poses every `step` over [t0, t1] (both ends included) as a Trajectory for the renderer,
    // or nullopt if any of them is stale. The renderer's per-pulse interpolation between these
    // knots then matches at() within the step's curvature.
    std::optional<PoseWindow> window(core::GpsTime t0, core::GpsTime t1, core::Nanos step) const;

    // Newest time present in both tracks (nullopt before the first full pose).
    std::optional<core::GpsTime> newest() const;

  private:
    struct PosSample {
        core::GpsTime t;
        Eigen::Vector3d p;
        std::optional<Eigen::Vector3d> v;
        MessageTag tag;
    };
    struct AttSample {
        core::GpsTime t;
        Eigen::Quaterniond q;
        MessageTag tag;
    };
    // The pose at t; the messages it used are appended to `used` when given.
    Query at_locked(core::GpsTime t, std::vector<UsedMessage>* used) const;
    Eigen::Vector3d velocity_at_end() const;

    PoseBufferConfig cfg_;
    mutable std::mutex mu_;
    std::deque<PosSample> pos_;
    std::deque<AttSample> att_;
};

}  // namespace mirage::navpose
