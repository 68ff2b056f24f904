// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>

#include "mirage/core/time.hpp"

namespace mirage::navpose {

// Which navigation message a track sample came from: its sequence number (the order the input
// decoded it in) and when it arrived (host CLOCK_MONOTONIC ns; 0 for a log read from a file).
// The live loop follows it into the packets rendered with the sample, to time INS -> packet.
struct MessageTag {
    std::uint64_t seq = 0;
    std::int64_t arrival_ns = 0;
};

// The two tracks a pose is made of: some protocols send them in different messages.
enum class Track : std::uint8_t { Position, Attitude };

// An accepted sample of the position track, in the scene frame.
struct PositionUpdate {
    core::GpsTime t{};
    Eigen::Vector3d local{Eigen::Vector3d::Zero()};  // grid E, N, up from the anchor
    std::optional<Eigen::Vector3d> velocity;         // local, when the message reported one
    // The first sample of a new track (after a long silence or a re-initialisation): nothing
    // may be interpolated between it and older samples.
    bool restart = false;
    MessageTag tag;
};

// An accepted sample of the attitude track, in the scene frame.
struct AttitudeUpdate {
    core::GpsTime t{};
    Eigen::Quaterniond attitude{Eigen::Quaterniond::Identity()};  // body FLU -> local ENU
    // The NED Euler angles applied (roll, pitch, heading; rad): a heading-only message's
    // heading with the roll and pitch it was combined with.
    Eigen::Vector3d ned_rpy{Eigen::Vector3d::Zero()};
    bool restart = false;
    MessageTag tag;
};

}  // namespace mirage::navpose
