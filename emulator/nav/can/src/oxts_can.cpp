// SPDX-License-Identifier: Apache-2.0
#include "mirage/navcan/oxts_can.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "bits.hpp"
#include "frames.hpp"

namespace mirage::navcan {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr std::int64_t kNsPerDay = 86'400 * core::kNsPerSecond;
// Days from 1970-01-01 to the GPS epoch 1980-01-06.
const std::int64_t kGpsEpochDays = detail::days_from_civil(1980, 1, 6);

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
    const std::int64_t q = a / b;
    return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

}  // namespace

OxtsCanDecoder::OxtsCanDecoder(OxtsCanConfig config) : config_(config) {
    const OxtsCanIds& ids = config_.ids;
    if (ids.lat_lon != 0) complete_mask_ |= kLatLon;
    if (ids.altitude != 0) complete_mask_ |= kAlt;
    if (ids.velocity != 0) complete_mask_ |= kVel;
    if (ids.heading_pitch_roll != 0) complete_mask_ |= kHpr;
}

bool OxtsCanDecoder::decode_into(const nav::CanFrame& f, std::uint32_t& part) {
    const OxtsCanIds& ids = config_.ids;
    const bool ext = ids.extended;
    const detail::Bytes8& d = f.data;
    auto need = [&](std::uint8_t len) {
        if (f.len >= len) return true;
        ++counters_.truncated;
        return false;
    };
    auto bad = [&] {
        ++counters_.invalid_field;
        return false;
    };
    nav::NavSample& s = group_;

    if (detail::matches(f, ids.date_time, ext)) {
        part = kDateTime;
        if (!need(8)) return false;
        const auto year = static_cast<std::int64_t>(d[1]) * 100 + d[0];
        const unsigned month = d[2], day = d[3], hsec = d[4], sec = d[5], min = d[6], hour = d[7];
        // GPS time has no leap seconds, so second 60 is invalid here.
        // Years outside 1980-2200 are no GPS time an INS sends, and would overflow int64 ns.
        if (d[0] > 99 || year < 1980 || year > 2200 || !detail::valid_date(year, month, day) ||
            hsec > 99 || sec > 59 || min > 59 || hour > 23) {
            return bad();
        }
        const std::int64_t days = detail::days_from_civil(year, month, day) - kGpsEpochDays;
        date_time_ns_ = days * kNsPerDay + ((hour * 3600 + min * 60 + sec) * core::kNsPerSecond) +
                        static_cast<std::int64_t>(hsec) * 10'000'000;
        return true;
    }
    if (detail::matches(f, ids.milli_time, ext)) {
        part = kMilliTime;
        if (!need(6)) return false;
        const std::int64_t ms = detail::get_s(d, 0, 48);
        // Beyond ~2272 the count would overflow int64 nanoseconds.
        if (ms < 0 || ms > std::numeric_limits<std::int64_t>::max() / 1'000'000) return bad();
        milli_time_ns_ = ms * 1'000'000;
        if (f.len >= 7) utc_offset_s_ = static_cast<int>(detail::get_s(d, 48, 8));
        return true;
    }
    if (detail::matches(f, ids.lat_lon, ext)) {
        part = kLatLon;
        if (!need(8)) return false;
        const std::int64_t lat = detail::get_s(d, 0, 32), lon = detail::get_s(d, 32, 32);
        if (lat < -900'000'000 || lat > 900'000'000 || lon < -1'800'000'000 ||
            lon > 1'800'000'000) {
            return bad();
        }
        s.lat_deg = static_cast<double>(lat) * 1e-7;
        s.lon_deg = static_cast<double>(lon) * 1e-7;
        return true;
    }
    if (detail::matches(f, ids.altitude, ext)) {
        part = kAlt;
        if (!need(4)) return false;
        s.height_m = static_cast<double>(detail::get_s(d, 0, 32)) * 1e-3;
        return true;
    }
    if (detail::matches(f, ids.velocity, ext)) {
        part = kVel;
        if (!need(6)) return false;
        // Already north, east, down (§7.1): no sign change.
        s.velocity_ned_mps = {static_cast<double>(detail::get_s(d, 0, 16)) * 0.01,
                              static_cast<double>(detail::get_s(d, 16, 16)) * 0.01,
                              static_cast<double>(detail::get_s(d, 32, 16)) * 0.01};
        return true;
    }
    if (detail::matches(f, ids.heading_pitch_roll, ext)) {
        part = kHpr;
        if (!need(6)) return false;
        const std::uint64_t heading = detail::get_u(d, 0, 16);
        const std::int64_t pitch = detail::get_s(d, 16, 16), roll = detail::get_s(d, 32, 16);
        if (heading >= 36'000 || pitch < -9'000 || pitch > 9'000 || roll < -18'000 ||
            roll > 18'000) {
            return bad();
        }
        s.heading_rad = static_cast<double>(heading) * 0.01 * kDegToRad;
        s.pitch_rad = static_cast<double>(pitch) * 0.01 * kDegToRad;
        s.roll_rad = static_cast<double>(roll) * 0.01 * kDegToRad;
        return true;
    }
    if (detail::matches(f, ids.accel_vehicle, ext)) {
        part = kAccel;
        if (!need(6)) return false;
        s.accel_frd_mps2 = {static_cast<double>(detail::get_s(d, 0, 16)) * 0.01,
                            static_cast<double>(detail::get_s(d, 16, 16)) * 0.01,
                            static_cast<double>(detail::get_s(d, 32, 16)) * 0.01};
        return true;
    }
    if (detail::matches(f, ids.rate_vehicle, ext)) {
        part = kRate;
        if (!need(6)) return false;
        s.rate_frd_radps = {static_cast<double>(detail::get_s(d, 0, 16)) * 0.01 * kDegToRad,
                            static_cast<double>(detail::get_s(d, 16, 16)) * 0.01 * kDegToRad,
                            static_cast<double>(detail::get_s(d, 32, 16)) * 0.01 * kDegToRad};
        return true;
    }
    part = 0;
    ++counters_.unsupported;
    return false;
}

void OxtsCanDecoder::close(const nav::SampleFn& on_sample) {
    const std::uint32_t parts = parts_;
    nav::NavSample s = group_;
    parts_ = 0;
    group_ = nav::NavSample{};
    group_stamped_ = false;
    if (parts == 0) return;

    const bool has_time = (parts & (kDateTime | kMilliTime)) != 0;
    const bool has_pos = (parts & (kLatLon | kAlt)) == (kLatLon | kAlt);
    const bool has_vel = (parts & kVel) != 0;
    const bool has_att = (parts & kHpr) != 0;
    if (!has_time || !(has_pos || has_vel || has_att)) {
        ++incomplete_groups_;
        return;
    }
    s.source = nav::Protocol::OxtsCan;
    s.fields = nav::NavSample::kTime;
    s.t = core::GpsTime{core::Nanos{(parts & kMilliTime) ? milli_time_ns_ : date_time_ns_}};
    if (has_pos) {
        s.fields |= nav::NavSample::kPosition;
        if (!config_.altitude_is_ellipsoidal) s.fields |= nav::NavSample::kHeightIsMsl;
    } else {
        s.lat_deg = s.lon_deg = s.height_m = 0.0;
    }
    if (has_vel) s.fields |= nav::NavSample::kVelocity;
    if (has_att) s.fields |= nav::NavSample::kAttitude;
    if (parts & kAccel) s.fields |= nav::NavSample::kAcceleration;
    if (parts & kRate) s.fields |= nav::NavSample::kAngularRate;
    have_emitted_ = true;
    emitted_cycle_ = floor_div(s.t.time_since_epoch().count(), 10'000'000);
    ++counters_.samples;
    on_sample(s);
}

void OxtsCanDecoder::feed(const nav::CanFrame& frame, const nav::SampleFn& on_sample) {
    if (frame.rtr || frame.error) {
        ++counters_.unsupported;
        return;
    }
    // Decode into a scratch copy so a bad frame leaves the group untouched, and a repeated
    // message type closes the old group before its values are overwritten.
    const nav::NavSample saved = group_;
    const std::int64_t saved_dt = date_time_ns_, saved_mt = milli_time_ns_;
    const int saved_off = utc_offset_s_;
    std::uint32_t part = 0;
    nav::NavSample fresh{};
    group_ = fresh;
    const bool ok = decode_into(frame, part);
    const nav::NavSample decoded = group_;
    const std::int64_t new_dt = date_time_ns_, new_mt = milli_time_ns_;
    const int new_off = utc_offset_s_;
    group_ = saved;
    date_time_ns_ = saved_dt;
    milli_time_ns_ = saved_mt;
    utc_offset_s_ = saved_off;
    if (!ok) return;
    ++counters_.messages_ok;

    constexpr std::int64_t k10ms = 10'000'000;
    // A time frame of the cycle just emitted (0x630 after 0x607 from a unit sending in ID
    // order) belongs to that sample, not to the next group.
    if (parts_ == 0 && have_emitted_ && (part == kDateTime || part == kMilliTime)) {
        const std::int64_t t = part == kDateTime ? new_dt : new_mt;
        if (floor_div(t, k10ms) == emitted_cycle_) {
            if (part == kMilliTime) utc_offset_s_ = new_off;
            return;
        }
    }
    // A repeated message type, or a time of another cycle, starts the next group.
    bool next_cycle = (parts_ & part) != 0;
    if (part == kDateTime && (parts_ & kMilliTime)) {
        next_cycle = next_cycle || floor_div(milli_time_ns_, k10ms) * k10ms != new_dt;
    }
    if (part == kMilliTime && (parts_ & kDateTime)) {
        next_cycle = next_cycle || floor_div(new_mt, k10ms) * k10ms != date_time_ns_;
    }
    if (next_cycle) close(on_sample);
    switch (part) {
        case kDateTime:
            date_time_ns_ = new_dt;
            break;
        case kMilliTime:
            milli_time_ns_ = new_mt;
            utc_offset_s_ = new_off;
            break;
        case kLatLon:
            group_.lat_deg = decoded.lat_deg;
            group_.lon_deg = decoded.lon_deg;
            break;
        case kAlt:
            group_.height_m = decoded.height_m;
            break;
        case kVel:
            group_.velocity_ned_mps = decoded.velocity_ned_mps;
            break;
        case kHpr:
            group_.heading_rad = decoded.heading_rad;
            group_.pitch_rad = decoded.pitch_rad;
            group_.roll_rad = decoded.roll_rad;
            break;
        case kAccel:
            group_.accel_frd_mps2 = decoded.accel_frd_mps2;
            break;
        case kRate:
            group_.rate_frd_radps = decoded.rate_frd_radps;
            break;
        default:
            break;
    }
    parts_ |= part;
    const bool has_time = (parts_ & (kDateTime | kMilliTime)) != 0;
    if (has_time && (parts_ & complete_mask_) == complete_mask_) close(on_sample);
}

void OxtsCanDecoder::feed(const nav::StampedCanFrame& frame, const nav::SampleFn& on_sample) {
    if (parts_ != 0 && group_stamped_ &&
        frame.time_ns - group_first_ns_ > config_.max_group_span_ns) {
        close(on_sample);
    }
    const bool was_empty = parts_ == 0;
    feed(frame.frame, on_sample);
    if (was_empty && parts_ != 0) {
        group_stamped_ = true;
        group_first_ns_ = frame.time_ns;
    }
}

void OxtsCanDecoder::flush(const nav::SampleFn& on_sample) { close(on_sample); }

std::vector<nav::CanFrame> oxts_can_encode(const nav::NavSample& s, const OxtsCanIds& ids,
                                           int utc_offset_s) {
    std::vector<nav::CanFrame> out;
    const bool ext = ids.extended;
    if (s.has(nav::NavSample::kTime)) {
        const std::int64_t ns = s.t.time_since_epoch().count();
        if (ids.date_time != 0) {
            // Calendar in the GPS time scale (no leap seconds), hundredths truncated.
            const std::int64_t day = floor_div(ns, kNsPerDay);
            const std::int64_t in_day = ns - day * kNsPerDay;
            const detail::Civil c = detail::civil_from_days(day + kGpsEpochDays);
            const std::int64_t sec_of_day = in_day / core::kNsPerSecond;
            detail::Bytes8 d{};
            d[0] = static_cast<std::uint8_t>(c.year % 100);
            d[1] = static_cast<std::uint8_t>(c.year / 100);
            d[2] = static_cast<std::uint8_t>(c.month);
            d[3] = static_cast<std::uint8_t>(c.day);
            d[4] = static_cast<std::uint8_t>((in_day % core::kNsPerSecond) / 10'000'000);
            d[5] = static_cast<std::uint8_t>(sec_of_day % 60);
            d[6] = static_cast<std::uint8_t>((sec_of_day / 60) % 60);
            d[7] = static_cast<std::uint8_t>(sec_of_day / 3600);
            out.push_back(detail::make_frame(ids.date_time, ext, 8, d));
        }
        if (ids.milli_time != 0) {
            detail::Bytes8 d{};
            detail::put(d, 0, 48, static_cast<std::uint64_t>(floor_div(ns, 1'000'000)));
            detail::put(d, 48, 8,
                        static_cast<std::uint64_t>(static_cast<std::int64_t>(utc_offset_s)));
            out.push_back(detail::make_frame(ids.milli_time, ext, 7, d));
        }
    }
    if (s.has(nav::NavSample::kPosition)) {
        if (ids.lat_lon != 0) {
            detail::Bytes8 d{};
            detail::put_s(d, 0, 32, s.lat_deg, 1e-7);
            detail::put_s(d, 32, 32, s.lon_deg, 1e-7);
            out.push_back(detail::make_frame(ids.lat_lon, ext, 8, d));
        }
        if (ids.altitude != 0) {
            detail::Bytes8 d{};
            detail::put_s(d, 0, 32, s.height_m, 1e-3);
            out.push_back(detail::make_frame(ids.altitude, ext, 4, d));
        }
    }
    if (s.has(nav::NavSample::kVelocity) && ids.velocity != 0) {
        const Eigen::Vector3d& v = s.velocity_ned_mps;
        detail::Bytes8 d{};
        detail::put_s(d, 0, 16, v.x(), 0.01);
        detail::put_s(d, 16, 16, v.y(), 0.01);
        detail::put_s(d, 32, 16, v.z(), 0.01);
        detail::put_u(d, 48, 16, std::hypot(v.x(), v.y()), 0.01);
        out.push_back(detail::make_frame(ids.velocity, ext, 8, d));
    }
    if (s.has(nav::NavSample::kAcceleration) && ids.accel_vehicle != 0) {
        detail::Bytes8 d{};
        for (unsigned i = 0; i < 3; ++i) {
            detail::put_s(d, 16 * i, 16, s.accel_frd_mps2[static_cast<Eigen::Index>(i)], 0.01);
        }
        out.push_back(detail::make_frame(ids.accel_vehicle, ext, 6, d));
    }
    if (s.has(nav::NavSample::kAngularRate) && ids.rate_vehicle != 0) {
        detail::Bytes8 d{};
        for (unsigned i = 0; i < 3; ++i) {
            detail::put_s(d, 16 * i, 16, s.rate_frd_radps[static_cast<Eigen::Index>(i)] * kRadToDeg,
                          0.01);
        }
        out.push_back(detail::make_frame(ids.rate_vehicle, ext, 6, d));
    }
    // 0x607 last: a decoder closes the group when it arrives (see OxtsCanDecoder).
    if ((s.has(nav::NavSample::kAttitude) || s.has(nav::NavSample::kHeading)) &&
        ids.heading_pitch_roll != 0) {
        const bool full = s.has(nav::NavSample::kAttitude);
        // Unsigned 0..359.99°: wrap first, and a value rounding up to 360.00 becomes 0.
        double hdg = std::fmod(s.heading_rad * kRadToDeg, 360.0);
        if (hdg < 0.0) hdg += 360.0;
        std::int64_t raw = detail::to_raw(hdg, 0.01, 0, 36'000);
        if (raw == 36'000) raw = 0;
        detail::Bytes8 d{};
        detail::put(d, 0, 16, static_cast<std::uint64_t>(raw));
        detail::put(d, 16, 16,
                    static_cast<std::uint64_t>(
                        detail::to_raw(full ? s.pitch_rad * kRadToDeg : 0.0, 0.01, -9'000, 9'000)));
        detail::put(d, 32, 16,
                    static_cast<std::uint64_t>(detail::to_raw(full ? s.roll_rad * kRadToDeg : 0.0,
                                                              0.01, -18'000, 18'000)));
        out.push_back(detail::make_frame(ids.heading_pitch_roll, ext, 6, d));
    }
    return out;
}

}  // namespace mirage::navcan
