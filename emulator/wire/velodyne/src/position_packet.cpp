// SPDX-License-Identifier: Apache-2.0
#include "mirage/velodyne/position_packet.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <vector>

#include "byte_io.hpp"
#include "mirage/velodyne/sensor_clock.hpp"

namespace mirage::velodyne {

std::uint8_t nmea_checksum(std::string_view body) {
    if (!body.empty() && body.front() == '$') body.remove_prefix(1);
    if (const auto star = body.find('*'); star != std::string_view::npos)
        body = body.substr(0, star);
    std::uint8_t x = 0;
    for (char c : body) x = static_cast<std::uint8_t>(x ^ static_cast<std::uint8_t>(c));
    return x;
}

namespace {

// ddmm.mmmm (width 2) or dddmm.mmmm (width 3) from |degrees|, rounded in 1e-4 minutes.
std::string nmea_angle(double deg, int width) {
    const long long total = std::llround(std::abs(deg) * 60.0 * 10'000.0);
    const long long d = total / 600'000, rem = total % 600'000;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%0*lld%02lld.%04lld", width, d, rem / 10'000, rem % 10'000);
    return buf;
}

}  // namespace

std::string gprmc_sentence(core::GpsTime t, const GeoFix& fix) {
    const UtcFields u = utc_fields(t);
    char head[64];
    std::snprintf(head, sizeof head, "GPRMC,%02d%02d%02d,%c,", u.hour, u.minute, u.second,
                  fix.valid ? 'A' : 'V');
    char tail[64];
    // Course in [0, 360) after rounding to the printed 0.1° (359.96 → 000.0, not 360.0).
    double course = std::round(std::fmod(std::fmod(fix.course_deg, 360.0) + 360.0, 360.0) * 10.0);
    if (course >= 3600.0) course = 0.0;
    course /= 10.0;
    std::snprintf(tail, sizeof tail, ",%05.1f,%05.1f,%02d%02d%02d,,,%c",
                  std::max(0.0, fix.speed_knots), course, u.day, u.month, u.year % 100,
                  fix.valid ? 'A' : 'N');
    std::string body = std::string(head) + nmea_angle(fix.lat_deg, 2) + ',' +
                       (fix.lat_deg < 0 ? 'S' : 'N') + ',' + nmea_angle(fix.lon_deg, 3) + ',' +
                       (fix.lon_deg < 0 ? 'W' : 'E') + tail;
    char cs[8];
    std::snprintf(cs, sizeof cs, "*%02X", nmea_checksum(body));
    return "$" + body + cs;
}

void encode_position(PositionLayout layout, core::GpsTime t, const GeoFix& fix,
                     const PositionPacketOptions& opt,
                     std::span<std::uint8_t, kPositionPacketSize> out) {
    std::uint8_t* o = out.data();
    std::memset(o, 0, kPositionPacketSize);
    switch (layout) {
        case PositionLayout::Hdl32e:
            // 3 × {gyro, temperature, accel_x, accel_y}, 12-bit two's complement in u16 words.
            for (std::size_t i = 0; i < 3; ++i) {
                const std::int16_t w[4] = {opt.imu.gyro[i], opt.imu.temperature[i],
                                           opt.imu.accel_x[i], opt.imu.accel_y[i]};
                for (std::size_t k = 0; k < 4; ++k)
                    detail::put_u16(
                        o + 14 + 8 * i + 2 * k,
                        static_cast<std::uint16_t>(static_cast<std::uint16_t>(w[k]) & 0x0FFFu));
            }
            break;
        case PositionLayout::Vlp32c:
            o[187] = 40;  // top board °C
            o[188] = 38;  // bottom board °C
            o[189] = 39;  // temperature at the last ADC calibration
            o[196] = 1;   // last ADC calibration: power-on
            o[kPpsOffset] = static_cast<std::uint8_t>(opt.pps);
            o[205] = 25;  // temperature at power-up
            break;
        case PositionLayout::Vlp16:
            o[kPpsOffset] = static_cast<std::uint8_t>(opt.pps);
            break;
        case PositionLayout::None:
            return;
    }
    detail::put_u32(o + kPositionTimestampOffset, micros_past_hour(t));
    const std::string s = gprmc_sentence(t, fix) + "\r\n";
    // 128 bytes reserved for the sentence in the newest layout; an RMC sentence is < 80.
    std::memcpy(o + kNmeaOffset, s.data(), std::min<std::size_t>(s.size(), 128));
}

const char* to_string(PositionStatus s) {
    switch (s) {
        case PositionStatus::Ok:
            return "ok";
        case PositionStatus::WrongSize:
            return "wrong size";
        case PositionStatus::NoSentence:
            return "no sentence";
        case PositionStatus::Unterminated:
            return "unterminated sentence";
        case PositionStatus::BadChecksum:
            return "bad checksum";
        case PositionStatus::BadTimestamp:
            return "bad timestamp";
    }
    return "?";
}

std::uint64_t PositionCounters::total() const {
    return std::accumulate(count.begin(), count.end(), std::uint64_t{0});
}

namespace {

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return -1;
}

bool digits(std::string_view s, std::size_t pos, std::size_t n, int& out) {
    if (pos + n > s.size()) return false;
    int v = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const char c = s[pos + i];
        if (c < '0' || c > '9') return false;
        v = 10 * v + (c - '0');
    }
    out = v;
    return true;
}

// "ddmm.mmmm" with `deg_digits` degree digits → degrees.
bool nmea_degrees(std::string_view f, std::size_t deg_digits, double& out) {
    int d = 0;
    if (!digits(f, 0, deg_digits, d)) return false;
    const std::string minutes(f.substr(deg_digits));
    if (minutes.empty()) return false;
    char* end = nullptr;
    const double m = std::strtod(minutes.c_str(), &end);
    if (end != minutes.c_str() + minutes.size() || !(m >= 0 && m < 60)) return false;
    out = d + m / 60.0;
    return true;
}

void parse_rmc(std::string_view s, DecodedPosition& out) {
    // s = "$GPRMC,time,status,lat,N,lon,E,speed,course,date,..." without "*hh".
    std::vector<std::string_view> f;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= s.size(); ++i)
        if (i == s.size() || s[i] == ',') {
            f.push_back(s.substr(start, i - start));
            start = i + 1;
        }
    if (f.size() < 10 || f[0].size() != 6 || f[0].substr(3) != "RMC") return;
    int hh = 0, mm = 0, ss = 0, dd = 0, mo = 0, yy = 0;
    if (!digits(f[1], 0, 2, hh) || !digits(f[1], 2, 2, mm) || !digits(f[1], 4, 2, ss)) return;
    if (!digits(f[9], 0, 2, dd) || !digits(f[9], 2, 2, mo) || !digits(f[9], 4, 2, yy)) return;
    double lat = 0, lon = 0;
    if (!nmea_degrees(f[3], 2, lat) || !nmea_degrees(f[5], 3, lon)) return;
    if (f[4] == "S") lat = -lat;
    if (f[6] == "W") lon = -lon;
    out.rmc = true;
    out.fix_valid = f[2] == "A";
    out.hour = hh;
    out.minute = mm;
    out.second = ss;
    out.day = dd;
    out.month = mo;
    out.year = yy < 80 ? 2000 + yy : 1900 + yy;
    out.lat_deg = lat;
    out.lon_deg = lon;
}

}  // namespace

PositionStatus decode_position(std::span<const std::uint8_t> bytes, DecodedPosition& out) {
    if (bytes.size() != kPositionPacketSize) return PositionStatus::WrongSize;
    const std::uint8_t* p = bytes.data();
    if (p[kNmeaOffset] != '$') return PositionStatus::NoSentence;
    // The sentence ends at '*' followed by two hex digits, inside the packet.
    std::size_t star = 0;
    for (std::size_t i = kNmeaOffset + 1; i < kPositionPacketSize; ++i) {
        if (p[i] == '*') {
            star = i;
            break;
        }
        if (p[i] < 0x20 || p[i] > 0x7E) return PositionStatus::Unterminated;
    }
    if (star == 0 || star + 2 >= kPositionPacketSize) return PositionStatus::Unterminated;
    const int h1 = hex_digit(static_cast<char>(p[star + 1]));
    const int h2 = hex_digit(static_cast<char>(p[star + 2]));
    if (h1 < 0 || h2 < 0) return PositionStatus::Unterminated;
    const std::string_view body(reinterpret_cast<const char*>(p + kNmeaOffset + 1),
                                star - kNmeaOffset - 1);
    if (nmea_checksum(body) != static_cast<std::uint8_t>(16 * h1 + h2))
        return PositionStatus::BadChecksum;
    const std::uint32_t ts = detail::get_u32(p + kPositionTimestampOffset);
    if (ts >= 3'600'000'000u) return PositionStatus::BadTimestamp;
    out = DecodedPosition{};
    out.timestamp_us = ts;
    out.pps = p[kPpsOffset];
    out.sentence.assign(reinterpret_cast<const char*>(p + kNmeaOffset), star + 3 - kNmeaOffset);
    parse_rmc(std::string_view(out.sentence).substr(0, star - kNmeaOffset), out);
    return PositionStatus::Ok;
}

}  // namespace mirage::velodyne
