// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdio>
#include <string>

#include "mirage/core/georef.hpp"
#include "mirage/core/trajectory.hpp"

namespace mirage::navproto {

// The --nav-log options of `mirage render` / `mirage emulate`.
struct NavLogResimInputs {
    std::string path;
    std::string protocol = "nmea";
    std::string origin;     // lat,lon,h: a tangent-plane frame; empty: the scene's georeference
    std::string nmea_date;  // NMEA logs without RMC/ZDA: YYYY-MM-DD
    double undulation_m = 0;
    core::Interpolation interpolation = core::Interpolation::Linear;
};

// Re-simulation of a recorded drive: the log read, decoded and mapped with the rules and
// counters of `mirage live` (nav_log_tracks), then merged into the trajectory to render. Writes
// the log's summary, the counters line live prints and the track sizes to `report` (if given).
// Throws ConfigError (bad options, no usable pose) or IoError (unreadable log), naming
// --nav-log.
core::Trajectory resimulate_nav_log(const NavLogResimInputs& in, const core::Georef& georef,
                                    std::FILE* report);

}  // namespace mirage::navproto
