// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "mirage/core/time.hpp"
#include "mirage/nav/nav_sample.hpp"
#include "mirage/nmea/nmea_decoder.hpp"

namespace mirage::nmea::test {

inline constexpr double kPi = 3.14159265358979323846;
inline double deg(double rad) { return rad * 180.0 / kPi; }
inline double rad(double deg) { return deg * kPi / 180.0; }

// GPS ns of a UTC text ("2014-02-19T20:41:32Z").
inline std::int64_t gps_ns(const std::string& utc) {
    return core::parse_time(utc).time_since_epoch().count();
}

// All samples of `text` fed in one piece.
inline std::vector<nav::NavSample> decode_all(NmeaDecoder& d, std::string_view text) {
    std::vector<nav::NavSample> out;
    d.feed(text, [&](const nav::NavSample& s) { out.push_back(s); });
    return out;
}

// Same, fed in random pieces of 0..max_piece bytes (0-length feeds included).
inline std::vector<nav::NavSample> decode_split(NmeaDecoder& d, std::string_view text,
                                                std::uint32_t seed, std::size_t max_piece) {
    std::vector<nav::NavSample> out;
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> len(0, max_piece);
    std::size_t pos = 0;
    while (pos < text.size()) {
        const std::size_t n = std::min(len(rng), text.size() - pos);
        d.feed(text.substr(pos, n), [&](const nav::NavSample& s) { out.push_back(s); });
        pos += n;
    }
    return out;
}

// Bit-identical comparison of everything a decoder sets.
inline bool same_sample(const nav::NavSample& a, const nav::NavSample& b) {
    return a.source == b.source && a.fields == b.fields && a.t == b.t && a.lat_deg == b.lat_deg &&
           a.lon_deg == b.lon_deg && a.height_m == b.height_m &&
           a.velocity_ned_mps == b.velocity_ned_mps && a.roll_rad == b.roll_rad &&
           a.pitch_rad == b.pitch_rad && a.heading_rad == b.heading_rad && a.quality == b.quality &&
           a.satellites == b.satellites;
}

}  // namespace mirage::nmea::test
