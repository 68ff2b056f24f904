// SPDX-License-Identifier: Apache-2.0
#include "mirage/nmea/sentences.hpp"

namespace mirage::nmea {
namespace {

// Each reader leaves `out` empty for an empty field and returns false for a bad one.
bool read_number(std::string_view f, std::optional<double>& out, double lo, double hi) {
    out.reset();
    if (f.empty()) return true;
    const auto v = parse_number(f);
    if (!v || *v < lo || *v > hi) return false;
    out = *v;
    return true;
}

bool read_int(std::string_view f, std::optional<int>& out, int lo, int hi) {
    out.reset();
    if (f.empty()) return true;
    out = parse_int(f, lo, hi);
    return out.has_value();
}

bool read_time(std::string_view f, std::optional<UtcTime>& out) {
    out.reset();
    if (f.empty()) return true;
    out = parse_utc_time(f);
    return out.has_value();
}

// A lat/lon pair of fields (value, hemisphere): both empty = no data.
bool read_lat(std::string_view v, std::string_view h, std::optional<double>& out) {
    out.reset();
    if (v.empty() && h.empty()) return true;
    out = parse_latitude(v, h);
    return out.has_value();
}

bool read_lon(std::string_view v, std::string_view h, std::optional<double>& out) {
    out.reset();
    if (v.empty() && h.empty()) return true;
    out = parse_longitude(v, h);
    return out.has_value();
}

constexpr double kMaxAbsHeight = 1e6;  // m; beyond any receiver's altitude limit
constexpr double kMaxSpeedKnots = 1e5;

ParseStatus status(bool ok) { return ok ? ParseStatus::Ok : ParseStatus::InvalidField; }

}  // namespace

// GGA: 1 UTC, 2-3 lat, 4-5 lon, 6 quality, 7 satellites, 8 HDOP, 9 altitude MSL, 10 M,
// 11 geoid separation, 12 M, 13 DGPS age, 14 station (§1; 0-based here).
ParseStatus parse_gga(const Sentence& s, Gga& out) {
    out = Gga{};
    std::optional<int> quality;
    bool ok = read_time(s.at(0), out.time) && read_lat(s.at(1), s.at(2), out.lat_deg) &&
              read_lon(s.at(3), s.at(4), out.lon_deg) && read_int(s.at(5), quality, 0, 8) &&
              read_int(s.at(6), out.satellites, 0, 255) &&
              read_number(s.at(7), out.hdop, 0.0, 1e4) &&
              read_number(s.at(8), out.altitude_msl_m, -kMaxAbsHeight, kMaxAbsHeight) &&
              read_number(s.at(10), out.geoid_separation_m, -1000.0, 1000.0);
    out.quality = quality.value_or(0);
    return status(ok);
}

// RMC: 1 UTC, 2 status, 3-4 lat, 5-6 lon, 7 SOG kn, 8 track, 9 ddmmyy, 10-11 magnetic
// variation, 12 FAA mode, 13 navigation status.
ParseStatus parse_rmc(const Sentence& s, Rmc& out) {
    out = Rmc{};
    const std::string_view st = s.at(1);
    if (st != "A" && st != "V") return ParseStatus::InvalidField;
    out.valid = st == "A";
    bool ok = read_time(s.at(0), out.time) && read_lat(s.at(2), s.at(3), out.lat_deg) &&
              read_lon(s.at(4), s.at(5), out.lon_deg) &&
              read_number(s.at(6), out.speed_knots, 0.0, kMaxSpeedKnots) &&
              read_number(s.at(7), out.track_deg, 0.0, 360.0);
    if (!ok) return ParseStatus::InvalidField;
    if (!s.at(8).empty()) {
        out.date = parse_ddmmyy(s.at(8));
        if (!out.date) return ParseStatus::InvalidField;
    }
    if (!read_number(s.at(9), out.magnetic_variation_deg, 0.0, 180.0)) {
        return ParseStatus::InvalidField;
    }
    if (out.magnetic_variation_deg) {
        if (s.at(10) == "W") {
            *out.magnetic_variation_deg = -*out.magnetic_variation_deg;
        } else if (s.at(10) != "E") {
            return ParseStatus::InvalidField;
        }
    }
    const std::string_view mode = s.at(11);
    if (mode.size() > 1 || (mode.size() == 1 && (mode[0] < 'A' || mode[0] > 'Z'))) {
        return ParseStatus::InvalidField;
    }
    out.mode = mode.empty() ? '\0' : mode[0];
    return ParseStatus::Ok;
}

// VTG: 1 course true, 2 T, 3 course magnetic, 4 M, 5 SOG kn, 6 N, 7 SOG km/h, 8 K, 9 mode;
// the old form has no unit letters: course true, course magnetic, knots, km/h.
ParseStatus parse_vtg(const Sentence& s, Vtg& out) {
    out = Vtg{};
    std::size_t knots = 4, kmh = 6;
    if (s.count == 4) {
        knots = 2;
        kmh = 3;
    } else if (s.count < 8) {
        return ParseStatus::InvalidField;
    }
    std::optional<double> speed_kmh;
    const bool ok = read_number(s.at(0), out.track_deg, 0.0, 360.0) &&
                    read_number(s.at(knots), out.speed_knots, 0.0, kMaxSpeedKnots) &&
                    read_number(s.at(kmh), speed_kmh, 0.0, kMaxSpeedKnots * 1.852);
    if (!out.speed_knots && speed_kmh) out.speed_knots = *speed_kmh / 1.852;  // 1 kn = 1.852 km/h
    return status(ok);
}

ParseStatus parse_hdt(const Sentence& s, Hdt& out) {
    out = Hdt{};
    return status(read_number(s.at(0), out.heading_deg, 0.0, 360.0));
}

// ZDA: 1 UTC, 2 day, 3 month, 4 year (4 digits), 5 zone hours, 6 zone minutes.
ParseStatus parse_zda(const Sentence& s, Zda& out) {
    out = Zda{};
    if (!read_time(s.at(0), out.time) || !read_int(s.at(4), out.zone_hours, -13, 13) ||
        !read_int(s.at(5), out.zone_minutes, 0, 59)) {
        return ParseStatus::InvalidField;
    }
    const std::string_view d = s.at(1), m = s.at(2), y = s.at(3);
    if (d.empty() && m.empty() && y.empty()) return ParseStatus::Ok;
    const auto day = parse_int(d, 1, 31);
    const auto month = parse_int(m, 1, 12);
    const auto year = y.size() == 4 ? parse_int(y, 0, 9999) : std::nullopt;
    if (!day || !month || !year || d.size() > 2 || m.size() > 2) return ParseStatus::InvalidField;
    out.date = make_date(*year, *month, *day);
    return status(out.date.has_value());
}

// $PASHR (OxTS): 1 UTC, 2 heading, 3 T, 4 roll, 5 pitch, 6 heave, 7-9 roll/pitch/heading σ,
// 10 aiding status, 11 IMU status. Ashtech's `$PASHR,POS,…` (and its other alphabetic
// sub-sentences) never has `T` in field 3: that is how gpsd tells them apart (processPASHR).
ParseStatus parse_pashr(const Sentence& s, Pashr& out) {
    out = Pashr{};
    if (s.at(2) != "T") return ParseStatus::Unsupported;
    const bool ok =
        read_time(s.at(0), out.time) && read_number(s.at(1), out.heading_deg, 0.0, 360.0) &&
        read_number(s.at(3), out.roll_deg, -180.0, 180.0) &&
        read_number(s.at(4), out.pitch_deg, -90.0, 90.0) &&
        read_number(s.at(5), out.heave_m, -1e4, 1e4) &&
        read_number(s.at(6), out.roll_sigma_deg, 0.0, 360.0) &&
        read_number(s.at(7), out.pitch_sigma_deg, 0.0, 360.0) &&
        read_number(s.at(8), out.heading_sigma_deg, 0.0, 360.0) &&
        read_int(s.at(9), out.aiding_status, 0, 99) && read_int(s.at(10), out.imu_status, 0, 99);
    return status(ok);
}

// $PTNL,AVR: 1 UTC, 2 yaw, 3 "Yaw", 4 tilt, 5 "Tilt", 6 roll, 7 "Roll", 8 range, 9 quality,
// 10 PDOP, 11 satellites (the tag is PTNL; "AVR" is field 0 here).
ParseStatus parse_ptnl_avr(const Sentence& s, PtnlAvr& out) {
    out = PtnlAvr{};
    if (s.at(0) != "AVR") return ParseStatus::Unsupported;
    std::optional<int> quality;
    const bool ok =
        read_time(s.at(1), out.time) && read_number(s.at(2), out.yaw_deg, -360.0, 360.0) &&
        read_number(s.at(4), out.tilt_deg, -90.0, 90.0) &&
        read_number(s.at(6), out.roll_deg, -180.0, 180.0) &&
        read_number(s.at(8), out.range_m, 0.0, 1e5) && read_int(s.at(9), quality, 0, 4) &&
        read_number(s.at(10), out.pdop, 0.0, 1e4) && read_int(s.at(11), out.satellites, 0, 255);
    out.quality = quality.value_or(0);
    return status(ok);
}

}  // namespace mirage::nmea
