// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <optional>

#include "mirage/nav/nav_sample.hpp"
#include "mirage/navpose/nav_counters.hpp"
#include "mirage/navpose/nav_frame.hpp"
#include "mirage/navpose/track_gate.hpp"
#include "mirage/navpose/track_update.hpp"

namespace mirage::navpose {

struct NavMapperConfig {
    double undulation_m = 0;  // added to heights an INS reports above MSL
    TrackGateConfig gate;
};

// What one sample changed: the track updates accepted (none when it was refused).
struct TrackUpdates {
    std::optional<PositionUpdate> position;
    std::optional<AttitudeUpdate> attitude;
};

// The one mapping from decoded navigation samples to scene-frame track updates, used by
// `mirage live`, by --nav-log re-simulation and by `mirage fake-ins --log`, with one set of
// rejection rules (docs/live-navigation.md). In order, per sample:
//  1. without a full time: counted no_time; without position, attitude or heading: no_pose;
//  2. NaN/Inf in any field it claims (or latitude beyond ±90°): not_finite, the whole sample;
//  3. position: height + undulation when above MSL, WGS84 -> scene frame, velocity NED -> local;
//     beyond core::kLocalRangeM of the anchor on an axis: outside_scene, the position refused;
//  4. attitude: NED Euler -> scene frame, with the meridian convergence at the newest position
//     (the frame's origin before any); a heading-only message (HDT, PTNL,AVR) takes the roll
//     and pitch of the newest attitude applied, or level before any;
//  5. each track update through the TrackGate (time backwards, duplicates, position jumps).
// Pure and single-threaded: the caller owns the storage (PoseBuffer, or a log's tracks).
class NavMapper {
  public:
    explicit NavMapper(NavFrame frame, NavMapperConfig config = {});

    TrackUpdates map(const nav::NavSample& s, MessageTag tag = {});
    const NavCounters& counters() const { return counters_; }
    const NavFrame& frame() const { return frame_; }

  private:
    std::optional<PositionUpdate> map_position(const nav::NavSample& s, MessageTag tag);
    std::optional<AttitudeUpdate> map_attitude(const nav::NavSample& s, MessageTag tag);
    // Counts a refused track update; true when accepted.
    bool tally(const GateVerdict& v);

    NavFrame frame_;
    NavMapperConfig cfg_;
    TrackGate gate_;
    NavCounters counters_;
    double lat_deg_ = 0, lon_deg_ = 0;     // newest position, for the convergence
    double roll_rad_ = 0, pitch_rad_ = 0;  // newest attitude applied, for headings alone
};

}  // namespace mirage::navpose
