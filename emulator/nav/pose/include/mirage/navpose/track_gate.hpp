// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Geometry>
#include <chrono>
#include <cstdint>
#include <optional>

#include "mirage/core/time.hpp"

namespace mirage::navpose {

struct TrackGateConfig {
    // A position further than this from the one predicted from the previous samples (constant
    // velocity) is a jump: rejected, never applied.
    double max_jump_m = 20.0;
    // After a silence this long a track starts afresh: there is no prediction to compare with.
    core::Nanos restart_after{std::chrono::seconds(2)};
};

enum class AddStatus : std::uint8_t {
    Accepted,
    Reinitialised,  // the tenth jump in a row: accepted as the start of a new track
    NotFinite,      // NaN / Inf in the mapped position, velocity or attitude
    Duplicate,      // same time as the newest sample of its track (another log of the same
                    // epoch): ignored, not an error
    TimeBackwards,  // older than the newest sample of its track
    PositionJump,   // beyond max_jump_m of the prediction
};

struct GateVerdict {
    AddStatus status = AddStatus::Accepted;
    bool restart = false;  // accepted as the first sample of a new track
    bool accepted() const {
        return status == AddStatus::Accepted || status == AddStatus::Reinitialised;
    }
};

// The rejection rules of the position and attitude tracks, in the scene frame (one set for live
// input and logs: docs/live-navigation.md). Keeps only what the rules need: the two newest
// accepted positions (for the constant-velocity prediction) and the newest attitude time.
class TrackGate {
  public:
    explicit TrackGate(TrackGateConfig config = {});

    GateVerdict position(core::GpsTime t, const Eigen::Vector3d& local,
                         const std::optional<Eigen::Vector3d>& velocity);
    GateVerdict attitude(core::GpsTime t, const Eigen::Quaterniond& attitude);

  private:
    struct Fix {
        core::GpsTime t;
        Eigen::Vector3d p;
        std::optional<Eigen::Vector3d> v;
    };
    Eigen::Vector3d predicted(core::GpsTime t) const;

    TrackGateConfig cfg_;
    std::optional<Fix> last_, before_last_;
    std::optional<core::GpsTime> last_attitude_;
    int consecutive_jumps_ = 0;
};

}  // namespace mirage::navpose
