// SPDX-License-Identifier: Apache-2.0
#include "mirage/nmea/nmea_encoder.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "mirage/core/time.hpp"
#include "mirage/nmea/fields.hpp"
#include "mirage/nmea/sentence.hpp"

namespace mirage::nmea {
namespace {

using nav::FixQuality;
using nav::NavSample;

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr std::int64_t kNsPerDay = 86'400 * core::kNsPerSecond;

std::int64_t pow10(int n) {
    std::int64_t p = 1;
    for (int i = 0; i < n; ++i) p *= 10;
    return p;
}

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
    const std::int64_t q = a / b;
    return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

// printf into a std::string (numbers only; 64 bytes is ample).
template <typename... Args>
std::string format(const char* fmt, Args... args) {
    char buf[64];
    const int n = std::snprintf(buf, sizeof buf, fmt, args...);
    return n > 0 ? std::string(buf, static_cast<std::size_t>(std::min(n, 63))) : std::string{};
}

// Fixed-point text with `decimals` places, zero-padded to `int_digits` integer digits, with an
// explicit sign when `plus` (e.g. "+00.83").
std::string fixed(double v, int decimals, int int_digits = 1, bool plus = false) {
    const int width = int_digits + (decimals > 0 ? decimals + 1 : 0) + (plus || v < 0 ? 1 : 0);
    return plus ? format("%+0*.*f", width, decimals, v) : format("%0*.*f", width, decimals, v);
}

// An angle in degrees rounded to `decimals`, wrapped into [0, 360) after rounding so that
// 359.9999 never prints as "360.00".
double wrap_rounded_deg(double deg, int decimals) {
    const double scale = static_cast<double>(pow10(decimals));
    double d = std::round(std::fmod(deg, 360.0) * scale) / scale;
    if (d < 0.0) d += 360.0;
    if (d >= 360.0) d -= 360.0;
    return d;
}

// UTC date and time of day of a GPS instant, rounded to `decimals` of a second.
struct UtcParts {
    Date date;
    std::int64_t tod_ns = 0;
};

UtcParts utc_parts(core::GpsTime t, int decimals) {
    const std::int64_t q = pow10(9 - decimals);
    const std::int64_t unix_ns = floor_div(core::unix_ns_from_gps(t) + q / 2, q) * q;
    const std::int64_t day = floor_div(unix_ns, kNsPerDay);
    return {Date::from_unix_days(day), unix_ns - day * kNsPerDay};
}

std::string hhmmss(const UtcParts& u, int decimals) {
    const std::int64_t s = u.tod_ns / core::kNsPerSecond;
    std::string out = format("%02lld%02lld%02lld", static_cast<long long>(s / 3600),
                             static_cast<long long>(s / 60 % 60), static_cast<long long>(s % 60));
    if (decimals > 0) {
        const std::int64_t frac = (u.tod_ns % core::kNsPerSecond) / pow10(9 - decimals);
        out += format(".%0*lld", decimals, static_cast<long long>(frac));
    }
    return out;
}

// `ddmm.mmmm,N` / `dddmm.mmmm,E` rounded in integer units of the last minutes digit, so a
// rounding to 60 minutes carries into the degrees.
std::string deg_min(double deg, int deg_digits, int decimals, char pos, char neg) {
    const std::int64_t unit = pow10(decimals);
    const std::int64_t per_deg = 60 * unit;
    const auto units =
        static_cast<std::int64_t>(std::llround(std::fabs(deg) * 60.0 * double(unit)));
    const std::int64_t d = units / per_deg;
    const std::int64_t rem = units % per_deg;
    std::string out = format("%0*lld%02lld", deg_digits, static_cast<long long>(d),
                             static_cast<long long>(rem / unit));
    if (decimals > 0) out += format(".%0*lld", decimals, static_cast<long long>(rem % unit));
    out += ',';
    out += deg < 0.0 && units != 0 ? neg : pos;
    return out;
}

int gga_quality_code(FixQuality q) {
    switch (q) {
        case FixQuality::None:
            return 0;
        case FixQuality::Autonomous:
            return 1;
        case FixQuality::Differential:
            return 2;
        case FixQuality::RtkFixed:
            return 4;
        case FixQuality::RtkFloat:
            return 5;
        case FixQuality::DeadReckoning:
            return 6;
        case FixQuality::Unknown:
            return 7;  // "manual input": not from a real fix
        case FixQuality::Simulated:
            return 8;
    }
    return 7;
}

int avr_quality_code(FixQuality q) {
    switch (q) {
        case FixQuality::None:
            return 0;
        case FixQuality::RtkFloat:
            return 2;
        case FixQuality::RtkFixed:
            return 3;
        case FixQuality::Differential:
            return 4;
        default:
            return 1;
    }
}

// FAA mode letter: 'A' in the options means "from the sample's quality".
char faa_mode(const NavSample& s, char option) {
    if (option != 'A') return option;
    if (!s.has(NavSample::kPosition)) return 'N';
    switch (s.quality) {
        case FixQuality::None:
            return 'N';
        case FixQuality::Differential:
            return 'D';
        case FixQuality::RtkFixed:
            return 'R';
        case FixQuality::RtkFloat:
            return 'F';
        case FixQuality::DeadReckoning:
            return 'E';
        case FixQuality::Simulated:
            return 'S';
        default:
            return 'A';
    }
}

bool has_heading(const NavSample& s) {
    return (s.fields & (NavSample::kHeading | NavSample::kAttitude)) != 0;
}

std::string time_field(const NavSample& s, int decimals) {
    return s.has(NavSample::kTime) ? hhmmss(utc_parts(s.t, decimals), decimals) : std::string{};
}

// Speed over ground (knots) and true track (degrees) fields from the NED velocity.
std::string speed_track(const NavSample& s, const EncodeOptions& o, bool vtg) {
    std::string sog, sog_kmh, track;
    if (s.has(NavSample::kVelocity)) {
        const double vn = s.velocity_ned_mps.x(), ve = s.velocity_ned_mps.y();
        const double speed = std::hypot(vn, ve);
        sog = fixed(speed / kKnotMps, o.speed_decimals, o.speed_int_digits);
        sog_kmh = fixed(speed * 3.6, o.speed_decimals, o.speed_int_digits);
        track = fixed(wrap_rounded_deg(std::atan2(ve, vn) * kRadToDeg, o.track_decimals),
                      o.track_decimals, o.track_int_digits);
    }
    if (vtg) return track + ",T,,M," + sog + ",N," + sog_kmh + ",K";
    return sog + ',' + track;
}

}  // namespace

std::string encode_gga(const NavSample& s, const EncodeOptions& o) {
    std::string b = o.talker + "GGA," + time_field(s, o.time_decimals) + ',';
    const bool pos = s.has(NavSample::kPosition);
    if (pos) {
        b += deg_min(s.lat_deg, 2, o.minute_decimals, 'N', 'S') + ',' +
             deg_min(s.lon_deg, 3, o.minute_decimals, 'E', 'W') + ',';
    } else {
        b += ",,,,";
    }
    b += std::to_string(pos ? gga_quality_code(s.quality) : 0) + ',';
    b += format("%02d", static_cast<int>(s.satellites)) + ',';
    b += fixed(o.hdop, o.hdop_decimals) + ',';
    if (pos && s.has(NavSample::kHeightIsMsl)) {
        b += fixed(s.height_m, o.height_decimals) + ",M,,M,,";
    } else if (pos) {
        // MSL = ellipsoidal height − geoid separation.
        b += fixed(s.height_m - o.geoid_separation_m, o.height_decimals) + ",M," +
             fixed(o.geoid_separation_m, o.height_decimals) + ",M,,";
    } else {
        b += ",M,,M,,";
    }
    return frame_sentence(b);
}

std::string encode_rmc(const NavSample& s, const EncodeOptions& o) {
    const bool valid = s.has(NavSample::kPosition) && s.quality != FixQuality::None;
    std::string b = o.talker + "RMC," + time_field(s, o.time_decimals) + (valid ? ",A," : ",V,");
    if (s.has(NavSample::kPosition)) {
        b += deg_min(s.lat_deg, 2, o.minute_decimals, 'N', 'S') + ',' +
             deg_min(s.lon_deg, 3, o.minute_decimals, 'E', 'W') + ',';
    } else {
        b += ",,,,";
    }
    b += speed_track(s, o, false) + ',';
    if (s.has(NavSample::kTime)) {
        const Date d = utc_parts(s.t, o.time_decimals).date;
        b += format("%02d%02d%02d", d.day, d.month, d.year % 100);
    }
    b += ',';
    if (o.magnetic_variation_deg) {
        const double v = *o.magnetic_variation_deg;
        b += fixed(std::fabs(v), 1, 3) + (v < 0 ? ",W" : ",E");
    } else {
        b += ',';
    }
    if (o.rmc_mode != '\0') {
        b += ',';
        b += faa_mode(s, o.rmc_mode);
    }
    return frame_sentence(b);
}

std::string encode_vtg(const NavSample& s, const EncodeOptions& o) {
    std::string b = o.talker + "VTG," + speed_track(s, o, true);
    if (o.rmc_mode != '\0') {
        b += ',';
        b += faa_mode(s, o.rmc_mode);
    }
    return frame_sentence(b);
}

std::string encode_hdt(const NavSample& s, const EncodeOptions& o) {
    std::string b = o.talker + "HDT,";
    if (has_heading(s)) {
        b += fixed(wrap_rounded_deg(s.heading_rad * kRadToDeg, o.heading_decimals),
                   o.heading_decimals);
    }
    return frame_sentence(b + ",T");
}

std::string encode_zda(const NavSample& s, const EncodeOptions& o) {
    std::string b = o.talker + "ZDA,";
    if (s.has(NavSample::kTime)) {
        const UtcParts u = utc_parts(s.t, o.time_decimals);
        b += hhmmss(u, o.time_decimals) +
             format(",%02d,%02d,%04d,", u.date.day, u.date.month, u.date.year);
    } else {
        b += ",,,,";
    }
    if (o.zda_zone_hours) {
        b += format("%02d,%02d", *o.zda_zone_hours, o.zda_zone_minutes);
    } else {
        b += ',';
    }
    return frame_sentence(b);
}

// OxTS $PASHR: roll/pitch in NavSample's aerospace convention unchanged (see the decoder).
std::string encode_pashr(const NavSample& s, const EncodeOptions& o) {
    std::string b = "PASHR," + time_field(s, o.pashr_time_decimals) + ',';
    if (has_heading(s)) b += fixed(wrap_rounded_deg(s.heading_rad * kRadToDeg, 2), 2, 3);
    b += ",T,";
    if (s.has(NavSample::kAttitude)) {
        b += fixed(s.roll_rad * kRadToDeg, 2, 2, true) + ',' +
             fixed(s.pitch_rad * kRadToDeg, 2, 2, true);
    } else {
        b += ',';
    }
    b += ',' + fixed(o.heave_m, 2, 2, true) + ',' + fixed(o.roll_sigma_deg, 3) + ',' +
         fixed(o.pitch_sigma_deg, 3) + ',' + fixed(o.heading_sigma_deg, 3) + ',' +
         std::to_string(o.aiding_status) + ',' + std::to_string(o.imu_status);
    return frame_sentence(b);
}

// Trimble $PTNL,AVR: yaw in (−180, 180], tilt = pitch; the roll field stays empty.
std::string encode_ptnl_avr(const NavSample& s, const EncodeOptions& o) {
    std::string b = "PTNL,AVR," + time_field(s, o.avr_time_decimals) + ',';
    if (has_heading(s)) {
        double yaw = wrap_rounded_deg(s.heading_rad * kRadToDeg, 4);
        if (yaw > 180.0) yaw -= 360.0;
        b += fixed(yaw, 4, 1, true) + ",Yaw," + fixed(s.pitch_rad * kRadToDeg, 4, 1, true);
    } else {
        b += ",Yaw,";
    }
    b += ",Tilt,,," + fixed(o.avr_range_m, 3) + ',' + std::to_string(avr_quality_code(s.quality)) +
         ',' + fixed(o.avr_pdop, 1) + ',' + std::to_string(s.satellites);
    return frame_sentence(b);
}

std::string encode_epoch(const NavSample& s, std::uint32_t which, const EncodeOptions& o) {
    std::string out;
    if (which & kZda) out += encode_zda(s, o);
    if (which & kRmc) out += encode_rmc(s, o);
    if (which & kGga) out += encode_gga(s, o);
    if (which & kVtg) out += encode_vtg(s, o);
    if (which & kHdt) out += encode_hdt(s, o);
    if (which & kPashr) out += encode_pashr(s, o);
    if (which & kPtnlAvr) out += encode_ptnl_avr(s, o);
    return out;
}

}  // namespace mirage::nmea
