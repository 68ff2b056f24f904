// SPDX-License-Identifier: Apache-2.0
#include "mirage/navproto/nav_log_resim.hpp"

#include <fmt/format.h>

#include "mirage/core/error.hpp"
#include "mirage/navproto/nav_log.hpp"

namespace mirage::navproto {
namespace {

navpose::NavFrame resim_frame(const std::string& origin, const core::Georef& georef) {
    if (!origin.empty()) return parse_nav_origin(origin);
    try {
        return navpose::NavFrame::from_georef(georef);
    } catch (const ConfigError& e) {
        throw ConfigError(fmt::format("--nav-log: {} (or give --nav-origin lat,lon,h)", e.what()));
    }
}

}  // namespace

core::Trajectory resimulate_nav_log(const NavLogResimInputs& in, const core::Georef& georef,
                                    std::FILE* report) {
    const NavProtocol proto = parse_nav_protocol(in.protocol);
    const navpose::NavFrame frame = resim_frame(in.origin, georef);
    NavLogOptions lo;
    lo.nmea_date = in.nmea_date;
    const NavLog log = read_nav_log(in.path, proto, lo);
    if (report) std::fprintf(report, "%s\n", nav_log_summary(log).c_str());
    NavTrackOptions to;
    to.mapper.undulation_m = in.undulation_m;
    to.interpolation = in.interpolation;
    NavTrackStats ts;
    core::Trajectory traj = nav_log_trajectory(log, frame, to, &ts);
    if (report)
        std::fprintf(
            report,
            "nav log: %s\nnav log: %llu positions, %llu attitudes -> %llu poses over %.3f s\n",
            navpose::nav_counters_line(log.stats.decode, ts.counters).c_str(),
            static_cast<unsigned long long>(ts.positions),
            static_cast<unsigned long long>(ts.attitudes),
            static_cast<unsigned long long>(ts.poses),
            double((traj.end() - traj.begin()).count()) * 1e-9);
    return traj;
}

}  // namespace mirage::navproto
