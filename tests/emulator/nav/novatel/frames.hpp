// SPDX-License-Identifier: Apache-2.0
#pragma once
// Test helpers: whole frames from log structs, and a decoder that collects samples.
#include <cstdint>
#include <vector>

#include "mirage/nav/nav_sample.hpp"
#include "mirage/novatel/decoder.hpp"
#include "mirage/novatel/frame.hpp"
#include "mirage/novatel/messages.hpp"

namespace mirage::novatel::test {

inline LongHeader header_at(std::uint16_t id, std::uint16_t week, std::uint32_t ms) {
    LongHeader h;
    h.message_id = id;
    h.week = week;
    h.ms_of_week = ms;
    return h;
}

inline std::vector<std::uint8_t> frame(const BestPos& m, std::uint16_t week = 2300,
                                       std::uint32_t ms = 1000) {
    return frame_long(header_at(kBestPosId, week, ms), pack(m));
}
inline std::vector<std::uint8_t> frame(const InsPvaX& m, std::uint16_t week = 2300,
                                       std::uint32_t ms = 1000) {
    return frame_long(header_at(kInsPvaXId, week, ms), pack(m));
}
inline std::vector<std::uint8_t> frame(const InsPvaS& m) {
    ShortHeader h;
    h.message_id = kInsPvaSId;
    h.week = static_cast<std::uint16_t>(m.week);
    h.ms_of_week = static_cast<std::uint32_t>(m.seconds_of_week * 1000.0);
    return frame_short(h, pack(m));
}

struct Collect {
    NovatelDecoder dec;
    std::vector<nav::NavSample> out;
    nav::SampleFn fn() {
        return [this](const nav::NavSample& s) { out.push_back(s); };
    }
    void feed(std::span<const std::uint8_t> b) { dec.feed(b, fn()); }
};

inline std::vector<nav::NavSample> decode(const std::vector<std::uint8_t>& bytes) {
    Collect c;
    c.feed(bytes);
    return c.out;
}

// A valid, solved INSPVAX / INSPVAS with the given attitude.
inline InsPvaX good_inspvax() {
    InsPvaX m;
    m.ins_status = kInsSolutionGood;
    m.position_type = kPosInsRtkFixed;
    m.lat_deg = 48.1;
    m.lon_deg = 11.5;
    m.height_msl_m = 500.0;
    return m;
}
inline InsPvaS good_inspvas() {
    InsPvaS m;
    m.week = 2300;
    m.seconds_of_week = 1.0;
    m.ins_status = kInsSolutionGood;
    m.lat_deg = 48.1;
    m.lon_deg = 11.5;
    m.height_m = 500.0;
    return m;
}

}  // namespace mirage::novatel::test
