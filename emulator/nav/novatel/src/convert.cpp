// SPDX-License-Identifier: Apache-2.0
#include "mirage/novatel/convert.hpp"

#include <cmath>
#include <numbers>

#include "mirage/core/time.hpp"

namespace mirage::novatel {
namespace {

using nav::FixQuality;
using nav::NavSample;

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Plausibility bounds: anything outside is a corrupt field, not a vehicle state.
constexpr double kMinHeightM = -10'000.0;
constexpr double kMaxHeightM = 100'000.0;
constexpr double kMaxUndulationM = 200.0;  // EGM96 spans about ±110 m
constexpr double kMaxSpeedMps = 2'000.0;
constexpr std::uint32_t kMsPerWeek = 604'800'000U;

bool finite_in(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

bool position_ok(double lat, double lon, double h_msl, double undulation) {
    return finite_in(lat, -90.0, 90.0) && finite_in(lon, -180.0, 180.0) &&
           finite_in(h_msl, kMinHeightM, kMaxHeightM) &&
           finite_in(undulation, -kMaxUndulationM, kMaxUndulationM);
}

bool pva_ok(double vn, double ve, double vu, double roll, double pitch, double azimuth) {
    return finite_in(vn, -kMaxSpeedMps, kMaxSpeedMps) &&
           finite_in(ve, -kMaxSpeedMps, kMaxSpeedMps) &&
           finite_in(vu, -kMaxSpeedMps, kMaxSpeedMps) && finite_in(roll, -180.0, 180.0) &&
           finite_in(pitch, -90.0, 90.0) && finite_in(azimuth, -360.0, 360.0);
}

// Azimuth (degrees clockwise from north, any sign) -> heading in [0, 2π).
double heading_from_azimuth(double azimuth_deg) {
    double h = std::fmod(azimuth_deg * kDegToRad, kTwoPi);
    if (h < 0.0) h += kTwoPi;
    if (h >= kTwoPi) h = 0.0;  // -tiny + 2π rounds to 2π
    return h;
}

void set_pva(NavSample& s, double vn, double ve, double vu, double roll, double pitch,
             double azimuth) {
    s.velocity_ned_mps = Eigen::Vector3d(vn, ve, -vu);  // Up -> Down
    s.roll_rad = roll * kDegToRad;                      // same axis and sign (see header)
    s.pitch_rad = pitch * kDegToRad;
    s.heading_rad = heading_from_azimuth(azimuth);
    s.fields |= NavSample::kVelocity | NavSample::kAttitude;
}

NavSample header_sample(const LongHeader& h) {
    NavSample s;
    s.source = nav::Protocol::Novatel;
    if (h.time_status >= kTimeApproximate) {
        s.t = core::from_week_time(h.week, static_cast<std::int64_t>(h.ms_of_week) * 1'000'000);
        s.fields |= NavSample::kTime;
    }
    return s;
}

}  // namespace

FixQuality quality_from_position_type(std::uint32_t t) {
    switch (t) {
        case kPosNone:
            return FixQuality::None;
        case kPosDopplerVelocity:
        case kPosSingle:
        case kPosInsPsrSp:
            return FixQuality::Autonomous;
        case kPosPsrDiff:
        case kPosWaas:
        case kPosInsSbas:
        case kPosInsPsrDiff:
        case kPosPppConverging:
        case kPosPpp:
        case kPosInsPppConverging:
        case kPosInsPpp:
            return FixQuality::Differential;
        case kPosL1Float:
        case kPosIonoFreeFloat:
        case kPosNarrowFloat:
        case kPosInsRtkFloat:
            return FixQuality::RtkFloat;
        case kPosL1Int:
        case kPosWideInt:
        case kPosNarrowInt:
        case kPosRtkDirectIns:
        case kPosInsRtkFixed:
            return FixQuality::RtkFixed;
        case kPosPropagated:
            return FixQuality::DeadReckoning;
        default:
            return FixQuality::Unknown;
    }
}

bool ins_status_has_solution(std::uint32_t s) {
    return s == kInsHighVariance || s == kInsSolutionGood || s == kInsSolutionFree ||
           s == kInsAlignmentComplete;
}

FixQuality quality_from_ins_status(std::uint32_t s) {
    if (!ins_status_has_solution(s)) return FixQuality::None;
    // SOLUTION_FREE: the INS runs without GNSS updates.
    return s == kInsSolutionFree ? FixQuality::DeadReckoning : FixQuality::Autonomous;
}

std::uint32_t position_type_for(FixQuality q) {
    switch (q) {
        case FixQuality::None:
            return kPosNone;
        case FixQuality::Differential:
            return kPosInsPsrDiff;
        case FixQuality::RtkFloat:
            return kPosInsRtkFloat;
        case FixQuality::RtkFixed:
            return kPosInsRtkFixed;
        case FixQuality::DeadReckoning:
            return kPosPropagated;
        case FixQuality::Unknown:
        case FixQuality::Autonomous:
        case FixQuality::Simulated:
            break;
    }
    return kPosInsPsrSp;
}

std::uint32_t ins_status_for(FixQuality q) {
    if (q == FixQuality::None) return kInsAligning;
    if (q == FixQuality::DeadReckoning) return kInsSolutionFree;
    return kInsSolutionGood;
}

std::optional<NavSample> to_sample(const LongHeader& h, const BestPos& m) {
    if (h.ms_of_week >= kMsPerWeek || h.week > core::kMaxGpsWeek) return std::nullopt;
    NavSample s = header_sample(h);
    s.satellites = m.svs_in_solution;
    if (m.solution_status != 0 || m.position_type == kPosNone) {
        s.quality = FixQuality::None;
        return s;
    }
    if (!position_ok(m.lat_deg, m.lon_deg, m.height_msl_m, m.undulation_m)) return std::nullopt;
    s.quality = quality_from_position_type(m.position_type);
    s.lat_deg = m.lat_deg;
    s.lon_deg = m.lon_deg;
    s.height_m = m.height_msl_m + static_cast<double>(m.undulation_m);  // MSL + N = ellipsoidal
    s.fields |= NavSample::kPosition;
    return s;
}

std::optional<NavSample> to_sample(const LongHeader& h, const InsPvaX& m) {
    if (h.ms_of_week >= kMsPerWeek || h.week > core::kMaxGpsWeek) return std::nullopt;
    NavSample s = header_sample(h);
    if (!ins_status_has_solution(m.ins_status)) {
        s.quality = FixQuality::None;
        return s;
    }
    if (!position_ok(m.lat_deg, m.lon_deg, m.height_msl_m, m.undulation_m) ||
        !pva_ok(m.vel_north_mps, m.vel_east_mps, m.vel_up_mps, m.roll_deg, m.pitch_deg,
                m.azimuth_deg))
        return std::nullopt;
    s.quality = m.ins_status == kInsSolutionFree ? FixQuality::DeadReckoning
                                                 : quality_from_position_type(m.position_type);
    s.lat_deg = m.lat_deg;
    s.lon_deg = m.lon_deg;
    s.height_m = m.height_msl_m + static_cast<double>(m.undulation_m);
    s.fields |= NavSample::kPosition;
    set_pva(s, m.vel_north_mps, m.vel_east_mps, m.vel_up_mps, m.roll_deg, m.pitch_deg,
            m.azimuth_deg);
    return s;
}

std::optional<NavSample> to_sample(const InsPvaS& m) {
    if (!finite_in(m.seconds_of_week, 0.0, 604'800.0) || m.seconds_of_week >= 604'800.0 ||
        m.week > static_cast<std::uint32_t>(core::kMaxGpsWeek))
        return std::nullopt;
    NavSample s;
    s.source = nav::Protocol::Novatel;
    if (m.week != 0) {
        const auto ns = static_cast<std::int64_t>(std::llround(m.seconds_of_week * 1e9));
        s.t = core::from_week_time(static_cast<std::int32_t>(m.week), ns);
        s.fields |= NavSample::kTime;
    }
    s.quality = quality_from_ins_status(m.ins_status);
    if (!ins_status_has_solution(m.ins_status)) return s;
    if (!position_ok(m.lat_deg, m.lon_deg, m.height_m, 0.0) ||
        !pva_ok(m.vel_north_mps, m.vel_east_mps, m.vel_up_mps, m.roll_deg, m.pitch_deg,
                m.azimuth_deg))
        return std::nullopt;
    s.lat_deg = m.lat_deg;
    s.lon_deg = m.lon_deg;
    s.height_m = m.height_m;  // already ellipsoidal
    s.fields |= NavSample::kPosition;
    set_pva(s, m.vel_north_mps, m.vel_east_mps, m.vel_up_mps, m.roll_deg, m.pitch_deg,
            m.azimuth_deg);
    return s;
}

namespace {
double msl_height(const NavSample& s, float undulation_m) {
    return s.has(NavSample::kHeightIsMsl) ? s.height_m
                                          : s.height_m - static_cast<double>(undulation_m);
}
double ellipsoidal_height(const NavSample& s, float undulation_m) {
    return s.has(NavSample::kHeightIsMsl) ? s.height_m + static_cast<double>(undulation_m)
                                          : s.height_m;
}
// Heading in [0, 2π) -> azimuth in [0, 360); roll/pitch only when the sample has them.
void fill_attitude(const NavSample& s, double& roll, double& pitch, double& azimuth) {
    const bool att = s.has(NavSample::kAttitude);
    roll = att ? s.roll_rad * kRadToDeg : 0.0;
    pitch = att ? s.pitch_rad * kRadToDeg : 0.0;
    azimuth = (att || s.has(NavSample::kHeading)) ? s.heading_rad * kRadToDeg : 0.0;
}
}  // namespace

BestPos bestpos_from(const NavSample& s, float undulation_m) {
    BestPos m;
    const bool pos = s.has(NavSample::kPosition) && s.quality != FixQuality::None;
    m.solution_status = pos ? 0U : 1U;  // 1 INSUFFICIENT_OBS
    m.position_type = pos ? position_type_for(s.quality) : kPosNone;
    m.lat_deg = s.lat_deg;
    m.lon_deg = s.lon_deg;
    m.height_msl_m = msl_height(s, undulation_m);
    m.undulation_m = undulation_m;
    m.svs_tracked = s.satellites;
    m.svs_in_solution = s.satellites;
    return m;
}

InsPvaX inspvax_from(const NavSample& s, float undulation_m) {
    InsPvaX m;
    m.ins_status = ins_status_for(s.quality);
    m.position_type = position_type_for(s.quality);
    m.lat_deg = s.lat_deg;
    m.lon_deg = s.lon_deg;
    m.height_msl_m = msl_height(s, undulation_m);
    m.undulation_m = undulation_m;
    m.vel_north_mps = s.velocity_ned_mps.x();
    m.vel_east_mps = s.velocity_ned_mps.y();
    m.vel_up_mps = -s.velocity_ned_mps.z();
    fill_attitude(s, m.roll_deg, m.pitch_deg, m.azimuth_deg);
    return m;
}

InsPvaS inspvas_from(const NavSample& s, float undulation_m) {
    InsPvaS m;
    const core::GpsWeekTime wt = core::to_week_time(s.t);
    m.week = static_cast<std::uint32_t>(wt.week);
    m.seconds_of_week = static_cast<double>(wt.ns_of_week) / 1e9;
    m.ins_status = ins_status_for(s.quality);
    m.lat_deg = s.lat_deg;
    m.lon_deg = s.lon_deg;
    m.height_m = ellipsoidal_height(s, undulation_m);
    m.vel_north_mps = s.velocity_ned_mps.x();
    m.vel_east_mps = s.velocity_ned_mps.y();
    m.vel_up_mps = -s.velocity_ned_mps.z();
    fill_attitude(s, m.roll_deg, m.pitch_deg, m.azimuth_deg);
    return m;
}

}  // namespace mirage::novatel
