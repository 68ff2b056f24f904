// SPDX-License-Identifier: Apache-2.0
#include "mirage/navpose/nav_counters.hpp"

#include <fmt/format.h>

namespace mirage::navpose {

std::string nav_counters_line(const nav::DecodeCounters& d, const NavCounters& c) {
    return fmt::format(
        "nav samples {} applied {}, decode rejected {} (bad checksum {}, truncated {}, invalid "
        "{}), pose rejected {} (time backwards {}, jumps {}, not finite {}, outside the scene {}), "
        "without time {}, "
        "without pose {}, duplicates {}, re-initialisations {}",
        c.samples, c.applied, d.rejected(), d.bad_checksum, d.truncated, d.invalid_field,
        c.rejected(), c.time_backwards, c.position_jumps, c.not_finite, c.outside_scene, c.no_time,
        c.no_pose, c.duplicates, c.reinitialisations);
}

}  // namespace mirage::navpose
