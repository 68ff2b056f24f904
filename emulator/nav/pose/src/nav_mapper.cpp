// SPDX-License-Identifier: Apache-2.0
#include "mirage/navpose/nav_mapper.hpp"

#include <cmath>

#include "mirage/core/georef.hpp"

namespace mirage::navpose {
namespace {

using F = nav::NavSample;

// NaN/Inf in a field the sample claims, or a latitude the projection cannot take.
bool finite_fields(const F& s) {
    if (s.has(F::kPosition) && (!std::isfinite(s.lat_deg) || !std::isfinite(s.lon_deg) ||
                                !std::isfinite(s.height_m) || std::abs(s.lat_deg) > 90.0))
        return false;
    if (s.has(F::kVelocity) && !s.velocity_ned_mps.allFinite()) return false;
    if (s.has(F::kAttitude) && (!std::isfinite(s.roll_rad) || !std::isfinite(s.pitch_rad) ||
                                !std::isfinite(s.heading_rad)))
        return false;
    return !s.has(F::kHeading) || std::isfinite(s.heading_rad);
}

}  // namespace

NavMapper::NavMapper(NavFrame frame, NavMapperConfig config)
    : frame_(frame), cfg_(config), gate_(config.gate) {
    const Eigen::Vector3d origin = frame_.geodetic_from_local(Eigen::Vector3d::Zero());
    lat_deg_ = origin.x();
    lon_deg_ = origin.y();
}

TrackUpdates NavMapper::map(const nav::NavSample& s, MessageTag tag) {
    ++counters_.samples;
    if (!s.has(F::kTime)) {
        ++counters_.no_time;
        return {};
    }
    if (!s.has(F::kPosition) && !s.has(F::kAttitude) && !s.has(F::kHeading)) {
        ++counters_.no_pose;
        return {};
    }
    if (!finite_fields(s)) {
        ++counters_.not_finite;
        return {};
    }
    TrackUpdates u;
    if (s.has(F::kPosition)) u.position = map_position(s, tag);
    if (s.has(F::kAttitude) || s.has(F::kHeading)) u.attitude = map_attitude(s, tag);
    if (u.position || u.attitude) ++counters_.applied;
    return u;
}

std::optional<PositionUpdate> NavMapper::map_position(const nav::NavSample& s, MessageTag tag) {
    lat_deg_ = s.lat_deg;
    lon_deg_ = s.lon_deg;
    PositionUpdate u;
    u.t = s.t;
    u.tag = tag;
    const double h = s.height_m + (s.has(F::kHeightIsMsl) ? cfg_.undulation_m : 0.0);
    u.local = frame_.local_from_geodetic(s.lat_deg, s.lon_deg, h);
    if (!(u.local.cwiseAbs().maxCoeff() < core::kLocalRangeM)) {  // another frame than the scene's
        ++counters_.outside_scene;
        return std::nullopt;
    }
    if (s.has(F::kVelocity))
        u.velocity = frame_.local_velocity(s.velocity_ned_mps, s.lat_deg, s.lon_deg);
    const GateVerdict v = gate_.position(u.t, u.local, u.velocity);
    if (!tally(v)) return std::nullopt;
    u.restart = v.restart;
    return u;
}

std::optional<AttitudeUpdate> NavMapper::map_attitude(const nav::NavSample& s, MessageTag tag) {
    const bool full = s.has(F::kAttitude);
    AttitudeUpdate u;
    u.t = s.t;
    u.tag = tag;
    u.ned_rpy = {full ? s.roll_rad : roll_rad_, full ? s.pitch_rad : pitch_rad_, s.heading_rad};
    u.attitude =
        frame_.local_attitude(u.ned_rpy.x(), u.ned_rpy.y(), u.ned_rpy.z(), lat_deg_, lon_deg_);
    const GateVerdict v = gate_.attitude(u.t, u.attitude);
    if (!tally(v)) return std::nullopt;
    u.restart = v.restart;
    roll_rad_ = u.ned_rpy.x();
    pitch_rad_ = u.ned_rpy.y();
    return u;
}

bool NavMapper::tally(const GateVerdict& v) {
    switch (v.status) {
        case AddStatus::Accepted:
            return true;
        case AddStatus::Reinitialised:
            ++counters_.reinitialisations;
            return true;
        case AddStatus::NotFinite:
            ++counters_.not_finite;
            break;
        case AddStatus::Duplicate:
            ++counters_.duplicates;
            break;
        case AddStatus::TimeBackwards:
            ++counters_.time_backwards;
            break;
        case AddStatus::PositionJump:
            ++counters_.position_jumps;
            break;
    }
    return false;
}

}  // namespace mirage::navpose
