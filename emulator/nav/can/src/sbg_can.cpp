// SPDX-License-Identifier: Apache-2.0
#include "mirage/navcan/sbg_can.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bits.hpp"
#include "frames.hpp"

namespace mirage::navcan {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kQuatFactor = 3.05185094759972e-5;  // 1/32767 (sbgCan.dbc EKF_QUAT)
constexpr std::int64_t kNsPerMs = 1'000'000;
constexpr std::int64_t kMsPerWeek = core::kSecondsPerWeek * 1000;

// SOLUTION_STATUS bits (§4).
constexpr std::uint32_t kAttitudeValid = 1u << 4;
constexpr std::uint32_t kHeadingValid = 1u << 5;
constexpr std::uint32_t kVelocityValid = 1u << 6;
constexpr std::uint32_t kPositionValid = 1u << 7;
constexpr std::uint32_t kGnss1PosUsed = 1u << 11;

// The full GPS time whose time of week is tow_ms, in the week nearest to `approx`.
std::int64_t gps_ns_near(std::int64_t approx_ns, std::uint32_t tow_ms) {
    const core::GpsWeekTime wt = core::to_week_time(core::GpsTime{core::Nanos{approx_ns}});
    std::int64_t best = 0;
    std::int64_t best_err = -1;
    for (std::int32_t w = wt.week - 1; w <= wt.week + 1; ++w) {
        const std::int64_t cand =
            core::from_week_time(w, static_cast<std::int64_t>(tow_ms) * kNsPerMs)
                .time_since_epoch()
                .count();
        const std::int64_t err = cand > approx_ns ? cand - approx_ns : approx_ns - cand;
        if (best_err < 0 || err < best_err) {
            best = cand;
            best_err = err;
        }
    }
    return best;
}

nav::FixQuality quality_of(std::uint32_t status) {
    switch (status & 0xFu) {
        case 4:
            return (status & kGnss1PosUsed) ? nav::FixQuality::Autonomous
                                            : nav::FixQuality::DeadReckoning;
        case 3:
            return nav::FixQuality::DeadReckoning;  // navigation velocity only
        default:
            return nav::FixQuality::None;  // uninitialised, vertical gyro, AHRS
    }
}

std::uint32_t device_us(core::GpsTime t, core::GpsTime boot) {
    const std::int64_t us = (t - boot).count() / 1000;
    return static_cast<std::uint32_t>(static_cast<std::uint64_t>(us) & 0xFFFF'FFFFu);
}

}  // namespace

SbgCanDecoder::SbgCanDecoder(SbgCanIds ids) : ids_(ids) {}

std::optional<core::GpsTime> SbgCanDecoder::gps_time_of(std::uint32_t device_us) const {
    if (!have_anchor_) return std::nullopt;
    // Wrap-safe difference of the 32-bit µs clock (wraps every 71.6 min).
    const auto diff = static_cast<std::int32_t>(device_us - anchor_ts_);
    return core::GpsTime{core::Nanos{anchor_gps_ns_ + static_cast<std::int64_t>(diff) * 1000}};
}

void SbgCanDecoder::close(const nav::SampleFn& on_sample) {
    if (!group_open_) return;
    group_open_ = false;
    const std::uint32_t parts = parts_;
    parts_ = 0;
    if (parts == 0) return;
    const auto t = gps_time_of(group_ts_);
    if (!t) {
        ++no_time_groups_;
        return;
    }
    nav::NavSample s = group_;
    s.source = nav::Protocol::SbgCan;
    s.t = *t;
    s.fields = nav::NavSample::kTime;
    bool att = (parts & (kEuler | kQuat)) != 0;
    bool pos = (parts & (kPos | kAlt)) == (kPos | kAlt);
    bool vel = (parts & kVel) != 0;
    if (have_status_) {
        att = att && (solution_status_ & kAttitudeValid) && (solution_status_ & kHeadingValid);
        pos = pos && (solution_status_ & kPositionValid);
        vel = vel && (solution_status_ & kVelocityValid);
        s.quality = quality_of(solution_status_);
    }
    if (att) {
        if (!(parts & kEuler)) {
            // ZYX Euler angles of the body->NED quaternion.
            const double w = quat_[0], x = quat_[1], y = quat_[2], z = quat_[3];
            s.roll_rad = std::atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y));
            s.pitch_rad = std::asin(std::clamp(2 * (w * y - z * x), -1.0, 1.0));
            s.heading_rad = std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
        }
        // Yaw ±π -> heading [0, 2π).
        if (s.heading_rad < 0) s.heading_rad += 2 * kPi;
        if (s.heading_rad >= 2 * kPi) s.heading_rad -= 2 * kPi;
        s.fields |= nav::NavSample::kAttitude;
    }
    if (pos) {
        // §4/§7.2: ellipsoid height = MSL altitude + undulation.
        s.height_m = altitude_msl_m_ + undulation_m_;
        s.fields |= nav::NavSample::kPosition;
    }
    if (vel) s.fields |= nav::NavSample::kVelocity;
    ++counters_.samples;
    on_sample(s);
}

void SbgCanDecoder::flush(const nav::SampleFn& on_sample) { close(on_sample); }

void SbgCanDecoder::feed(const nav::CanFrame& f, const nav::SampleFn& on_sample) {
    if (f.rtr || f.error) {
        ++counters_.unsupported;
        return;
    }
    const bool ext = ids_.extended;
    const detail::Bytes8& d = f.data;
    auto need = [&](std::uint8_t len) {
        if (f.len >= len) return true;
        ++counters_.truncated;
        return false;
    };

    if (detail::matches(f, ids_.utc_0, ext)) {
        if (!need(8)) return;
        const auto ts = static_cast<std::uint32_t>(detail::get_u(d, 0, 32));
        const auto tow = static_cast<std::uint32_t>(detail::get_u(d, 32, 32));
        if (tow >= kMsPerWeek) {
            ++counters_.invalid_field;
            return;
        }
        ++counters_.messages_ok;
        utc0_pending_ = true;
        utc0_ts_ = ts;
        utc0_tow_ms_ = tow;
        if (have_anchor_) {
            // The week follows from the previous mapping until UTC_1 confirms it.
            const std::int64_t approx = gps_time_of(ts)->time_since_epoch().count();
            anchor_gps_ns_ = gps_ns_near(approx, tow);
            anchor_ts_ = ts;
        }
        return;
    }
    if (detail::matches(f, ids_.utc_1, ext)) {
        if (!need(8)) return;
        const std::int64_t year = 2000 + d[0];
        const unsigned month = d[1], day = d[2], hour = d[3], min = d[4], sec = d[5];
        const std::uint64_t sub_100us = detail::get_u(d, 48, 16);
        // SEC = 60 during an inserted leap second (§12.3).
        if (!detail::valid_date(year, month, day) || hour > 23 || min > 59 || sec > 60 ||
            sub_100us > 9999) {
            ++counters_.invalid_field;
            return;
        }
        ++counters_.messages_ok;
        if (!utc0_pending_) return;  // UTC_1 only fixes the week of a UTC_0's time of week
        const std::int64_t unix_s =
            detail::days_from_civil(year, month, day) * 86'400 + hour * 3600 + min * 60 + sec;
        const std::int64_t approx =
            core::gps_from_unix_ns(unix_s * core::kNsPerSecond).time_since_epoch().count();
        anchor_gps_ns_ = gps_ns_near(approx, utc0_tow_ms_);
        anchor_ts_ = utc0_ts_;
        have_anchor_ = true;
        utc0_pending_ = false;
        return;
    }
    if (detail::matches(f, ids_.status_03, ext)) {
        if (!need(4)) return;
        ++counters_.messages_ok;
        solution_status_ = static_cast<std::uint32_t>(detail::get_u(d, 0, 32));
        have_status_ = true;
        return;
    }
    if (detail::matches(f, ids_.ekf_info, ext)) {
        if (!need(4)) return;
        ++counters_.messages_ok;
        const auto ts = static_cast<std::uint32_t>(detail::get_u(d, 0, 32));
        if (group_open_ && ts == group_ts_) return;  // repeated EKF_INFO of the same epoch
        close(on_sample);
        group_open_ = true;
        group_ts_ = ts;
        parts_ = 0;
        group_ = nav::NavSample{};
        return;
    }

    std::uint32_t part = 0;
    if (detail::matches(f, ids_.ekf_quat, ext)) {
        if (!need(8)) return;
        double q[4];
        for (unsigned i = 0; i < 4; ++i) {
            q[i] = static_cast<double>(detail::get_s(d, 16 * i, 16)) * kQuatFactor;
        }
        const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (n < 0.9 || n > 1.1) {
            ++counters_.invalid_field;
            return;
        }
        if (!group_open_) {
            ++orphan_frames_;
            return;
        }
        for (unsigned i = 0; i < 4; ++i) quat_[i] = q[i] / n;
        part = kQuat;
    } else if (detail::matches(f, ids_.ekf_euler, ext)) {
        if (!need(6)) return;
        const std::int64_t r = detail::get_s(d, 0, 16), p = detail::get_s(d, 16, 16),
                           y = detail::get_s(d, 32, 16);
        // ±π for roll/yaw, ±π/2 for pitch, in 1e-4 rad.
        if (r < -31'416 || r > 31'416 || p < -15'708 || p > 15'708 || y < -31'416 || y > 31'416) {
            ++counters_.invalid_field;
            return;
        }
        if (!group_open_) {
            ++orphan_frames_;
            return;
        }
        group_.roll_rad = static_cast<double>(r) * 1e-4;
        group_.pitch_rad = static_cast<double>(p) * 1e-4;
        group_.heading_rad = static_cast<double>(y) * 1e-4;
        part = kEuler;
    } else if (detail::matches(f, ids_.ekf_pos, ext)) {
        if (!need(8)) return;
        const std::int64_t lat = detail::get_s(d, 0, 32), lon = detail::get_s(d, 32, 32);
        if (lat < -900'000'000 || lat > 900'000'000 || lon < -1'800'000'000 ||
            lon > 1'800'000'000) {
            ++counters_.invalid_field;
            return;
        }
        if (!group_open_) {
            ++orphan_frames_;
            return;
        }
        group_.lat_deg = static_cast<double>(lat) * 1e-7;
        group_.lon_deg = static_cast<double>(lon) * 1e-7;
        part = kPos;
    } else if (detail::matches(f, ids_.ekf_altitude, ext)) {
        if (!need(6)) return;
        if (!group_open_) {
            ++orphan_frames_;
            return;
        }
        altitude_msl_m_ = static_cast<double>(detail::get_s(d, 0, 32)) * 1e-3;
        undulation_m_ = static_cast<double>(detail::get_s(d, 32, 16)) * 0.005;
        part = kAlt;
    } else if (detail::matches(f, ids_.ekf_vel_ned, ext)) {
        if (!need(6)) return;
        if (!group_open_) {
            ++orphan_frames_;
            return;
        }
        group_.velocity_ned_mps = {static_cast<double>(detail::get_s(d, 0, 16)) * 0.01,
                                   static_cast<double>(detail::get_s(d, 16, 16)) * 0.01,
                                   static_cast<double>(detail::get_s(d, 32, 16)) * 0.01};
        part = kVel;
    } else {
        ++counters_.unsupported;
        return;
    }
    ++counters_.messages_ok;
    parts_ |= part;
    const bool att = (parts_ & (kEuler | kQuat)) != 0;
    if (att && (parts_ & (kPos | kAlt | kVel)) == (kPos | kAlt | kVel)) close(on_sample);
}

std::vector<nav::CanFrame> sbg_can_encode_utc(core::GpsTime t, const SbgCanEncoderConfig& cfg) {
    std::vector<nav::CanFrame> out;
    const bool ext = cfg.ids.extended;
    const std::int64_t ns = t.time_since_epoch().count();
    const std::int64_t ms_ns = ns - (((ns % kNsPerMs) + kNsPerMs) % kNsPerMs);
    const core::GpsTime t_ms{core::Nanos{ms_ns}};
    const core::GpsWeekTime wt = core::to_week_time(t_ms);
    if (cfg.ids.utc_0 != 0) {
        detail::Bytes8 d{};
        detail::put(d, 0, 32, device_us(t_ms, cfg.boot));
        detail::put(d, 32, 32, static_cast<std::uint64_t>(wt.ns_of_week / kNsPerMs));
        out.push_back(detail::make_frame(cfg.ids.utc_0, ext, 8, d));
    }
    if (cfg.ids.utc_1 != 0) {
        const std::int64_t unix_ns = core::unix_ns_from_gps(t_ms);
        constexpr std::int64_t kNsPerDay = 86'400 * core::kNsPerSecond;
        const std::int64_t day = unix_ns / kNsPerDay - (unix_ns % kNsPerDay < 0 ? 1 : 0);
        const std::int64_t in_day = unix_ns - day * kNsPerDay;
        const detail::Civil c = detail::civil_from_days(day);
        const std::int64_t sec = in_day / core::kNsPerSecond;
        detail::Bytes8 d{};
        d[0] = static_cast<std::uint8_t>(c.year - 2000);
        d[1] = static_cast<std::uint8_t>(c.month);
        d[2] = static_cast<std::uint8_t>(c.day);
        d[3] = static_cast<std::uint8_t>(sec / 3600);
        d[4] = static_cast<std::uint8_t>((sec / 60) % 60);
        d[5] = static_cast<std::uint8_t>(sec % 60);
        detail::put(d, 48, 16, static_cast<std::uint64_t>((in_day % core::kNsPerSecond) / 100'000));
        out.push_back(detail::make_frame(cfg.ids.utc_1, ext, 8, d));
    }
    return out;
}

std::vector<nav::CanFrame> sbg_can_encode(const nav::NavSample& s, const SbgCanEncoderConfig& cfg) {
    std::vector<nav::CanFrame> out;
    const SbgCanIds& ids = cfg.ids;
    const bool ext = ids.extended;
    if (ids.status_03 != 0) {
        detail::Bytes8 d{};
        detail::put(d, 0, 32, cfg.solution_status);
        out.push_back(detail::make_frame(ids.status_03, ext, 6, d));
    }
    {
        detail::Bytes8 d{};
        detail::put(d, 0, 32, device_us(s.t, cfg.boot));
        out.push_back(detail::make_frame(ids.ekf_info, ext, 4, d));
    }
    if (s.has(nav::NavSample::kAttitude)) {
        // Heading [0, 2π) -> yaw ±π.
        double yaw = std::remainder(s.heading_rad, 2 * kPi);
        const double cr = std::cos(s.roll_rad / 2), sr = std::sin(s.roll_rad / 2);
        const double cp = std::cos(s.pitch_rad / 2), sp = std::sin(s.pitch_rad / 2);
        const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
        if (ids.ekf_quat != 0) {
            const double q[4] = {cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
                                 cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy};
            detail::Bytes8 d{};
            for (unsigned i = 0; i < 4; ++i) detail::put_s(d, 16 * i, 16, q[i], kQuatFactor);
            out.push_back(detail::make_frame(ids.ekf_quat, ext, 8, d));
        }
        if (ids.ekf_euler != 0) {
            detail::Bytes8 d{};
            detail::put(
                d, 0, 16,
                static_cast<std::uint64_t>(detail::to_raw(s.roll_rad, 1e-4, -31'416, 31'416)));
            detail::put(
                d, 16, 16,
                static_cast<std::uint64_t>(detail::to_raw(s.pitch_rad, 1e-4, -15'708, 15'708)));
            detail::put(d, 32, 16,
                        static_cast<std::uint64_t>(detail::to_raw(yaw, 1e-4, -31'416, 31'416)));
            out.push_back(detail::make_frame(ids.ekf_euler, ext, 6, d));
        }
    }
    if (s.has(nav::NavSample::kPosition)) {
        if (ids.ekf_pos != 0) {
            detail::Bytes8 d{};
            detail::put_s(d, 0, 32, s.lat_deg, 1e-7);
            detail::put_s(d, 32, 32, s.lon_deg, 1e-7);
            out.push_back(detail::make_frame(ids.ekf_pos, ext, 8, d));
        }
        if (ids.ekf_altitude != 0) {
            // ALTITUDE is MSL: ellipsoidal height − undulation (an MSL sample is already MSL).
            const double msl =
                s.has(nav::NavSample::kHeightIsMsl) ? s.height_m : s.height_m - cfg.undulation_m;
            detail::Bytes8 d{};
            detail::put_s(d, 0, 32, msl, 1e-3);
            detail::put_s(d, 32, 16, cfg.undulation_m, 0.005);
            out.push_back(detail::make_frame(ids.ekf_altitude, ext, 6, d));
        }
    }
    if (s.has(nav::NavSample::kVelocity) && ids.ekf_vel_ned != 0) {
        detail::Bytes8 d{};
        for (unsigned i = 0; i < 3; ++i) {
            detail::put_s(d, 16 * i, 16, s.velocity_ned_mps[static_cast<Eigen::Index>(i)], 0.01);
        }
        out.push_back(detail::make_frame(ids.ekf_vel_ned, ext, 6, d));
    }
    return out;
}

}  // namespace mirage::navcan
