// SPDX-License-Identifier: Apache-2.0
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <iterator>

#include "mirage/core/error.hpp"
#include "mirage/navproto/nav_log.hpp"

namespace mirage::navproto {
namespace {

constexpr std::int64_t kExtrapolateNs = 1'000'000'000;

std::int64_t ns(core::GpsTime t) { return t.time_since_epoch().count(); }

// Linear between fixes; outside them, dead-reckoned up to 1 s with the end fix's velocity.
Eigen::Vector3d position_at(const std::vector<navpose::PositionUpdate>& pos, core::GpsTime t) {
    const auto hi = std::lower_bound(pos.begin(), pos.end(), t,
                                     [](const auto& u, core::GpsTime x) { return u.t < x; });
    if (hi != pos.end() && hi->t == t) return hi->local;
    if (hi != pos.begin() && hi != pos.end()) {
        const auto& lo = *std::prev(hi);
        const double f = double(ns(t) - ns(lo.t)) / double(ns(hi->t) - ns(lo.t));
        return lo.local + f * (hi->local - lo.local);
    }
    const auto& end = hi == pos.end() ? pos.back() : pos.front();
    const std::int64_t dt = ns(t) - ns(end.t);
    if (!end.velocity || std::llabs(dt) > kExtrapolateNs) return end.local;
    return end.local + *end.velocity * (double(dt) * 1e-9);
}

// Slerp between attitude samples, held outside.
Eigen::Quaterniond attitude_at(const std::vector<navpose::AttitudeUpdate>& att, core::GpsTime t) {
    const auto hi = std::lower_bound(att.begin(), att.end(), t,
                                     [](const auto& u, core::GpsTime x) { return u.t < x; });
    if (hi == att.end()) return att.back().attitude;
    if (hi->t == t || hi == att.begin()) return hi->attitude;
    const auto& lo = *std::prev(hi);
    const double f = double(ns(t) - ns(lo.t)) / double(ns(hi->t) - ns(lo.t));
    return lo.attitude.slerp(f, hi->attitude);
}

}  // namespace

NavTracks nav_log_tracks(const NavLog& log, const navpose::NavFrame& frame,
                         const navpose::NavMapperConfig& config) {
    NavTracks tracks;
    navpose::NavMapper mapper(frame, config);
    for (std::size_t i = 0; i < log.samples.size(); ++i) {
        navpose::TrackUpdates u = mapper.map(log.samples[i], {i, 0});
        if (u.position) tracks.positions.push_back(*u.position);
        if (u.attitude) tracks.attitudes.push_back(*u.attitude);
    }
    tracks.counters = mapper.counters();
    return tracks;
}

core::Trajectory nav_log_trajectory(const NavLog& log, const navpose::NavFrame& frame,
                                    const NavTrackOptions& options, NavTrackStats* stats_out) {
    const NavTracks tr = nav_log_tracks(log, frame, options.mapper);
    NavTrackStats st;
    st.positions = tr.positions.size();
    st.attitudes = tr.attitudes.size();
    st.counters = tr.counters;
    if (tr.positions.empty() || tr.attitudes.empty())
        throw ConfigError(fmt::format(
            "nav log '{}': no usable pose ({} positions, {} attitudes from {} samples; {} "
            "rejected messages, {} rejected samples) — is --nav-protocol {} right?",
            log.path, st.positions, st.attitudes, log.samples.size(), log.stats.rejected(),
            tr.counters.rejected(), to_string(log.protocol)));
    // Both tracks' times are increasing (the rules refuse the rest): merge them.
    std::vector<core::GpsTime> times;
    times.reserve(tr.positions.size() + tr.attitudes.size());
    for (const auto& u : tr.positions) times.push_back(u.t);
    for (const auto& u : tr.attitudes) times.push_back(u.t);
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    std::vector<core::StampedPose> samples;
    samples.reserve(times.size());
    for (const core::GpsTime t : times)
        samples.push_back({t, {position_at(tr.positions, t), attitude_at(tr.attitudes, t)}});
    st.poses = samples.size();
    if (stats_out) *stats_out = st;
    return core::Trajectory(std::move(samples), options.interpolation);
}

}  // namespace mirage::navproto
