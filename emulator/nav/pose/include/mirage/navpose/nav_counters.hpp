// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>

#include "mirage/nav/decode_counters.hpp"

namespace mirage::navpose {

// What the mapper did with the decoded samples, with the same names for live input, logs
// re-simulated with --nav-log and logs replayed by `mirage fake-ins --log`. Every sample lands
// in exactly one of applied, no_time, no_pose, not_finite or "all its track updates refused";
// the refusals are counted per track update (a NovAtel INSPVA stamped in the past refuses its
// position and its attitude: two time_backwards).
struct NavCounters {
    std::uint64_t samples = 0;         // decoded samples offered
    std::uint64_t applied = 0;         // samples that updated at least one track
    std::uint64_t no_time = 0;         // without a full time (NMEA HDT/VTG): never applied
    std::uint64_t no_pose = 0;         // timed, but no position, attitude or heading (RMC, ZDA)
    std::uint64_t not_finite = 0;      // NaN/Inf (or latitude beyond ±90°) in a field it claims
    std::uint64_t time_backwards = 0;  // track updates older than their track's newest
    std::uint64_t position_jumps = 0;  // positions beyond --max-jump-m of the prediction
    std::uint64_t reinitialisations = 0;  // the tenth jump in a row: applied as a new track
    std::uint64_t duplicates = 0;         // track updates at their track's newest time: ignored
    std::uint64_t outside_scene = 0;  // positions beyond core::kLocalRangeM of the scene's anchor

    // Rejected and never applied.
    std::uint64_t rejected() const {
        return not_finite + time_backwards + position_jumps + outside_scene;
    }
};

// One line, the same wherever navigation is read: "nav samples 120 applied 110, decode
// rejected 2 (bad checksum 1, truncated 0, invalid 1), pose rejected 3 (time backwards 2,
// jumps 1, not finite 0), without time 4, without pose 3, duplicates 0, re-initialisations 0".
std::string nav_counters_line(const nav::DecodeCounters& decode, const NavCounters& track);

}  // namespace mirage::navpose
