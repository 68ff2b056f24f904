// SPDX-License-Identifier: Apache-2.0
#include "mirage/novatel/encoder.hpp"

#include "mirage/core/time.hpp"
#include "mirage/novatel/convert.hpp"
#include "mirage/novatel/frame.hpp"
#include "mirage/novatel/messages.hpp"

namespace mirage::novatel {
namespace {

LongHeader long_header(const EncoderOptions& o, std::uint16_t id, const nav::NavSample& s) {
    LongHeader h;
    h.message_id = id;
    h.port_address = o.port_address;
    h.receiver_status = o.receiver_status;
    h.software_build = o.software_build;
    if (s.has(nav::NavSample::kTime)) {
        const core::GpsWeekTime wt = core::to_week_time(s.t);
        h.week = static_cast<std::uint16_t>(wt.week);
        h.ms_of_week = static_cast<std::uint32_t>(wt.ns_of_week / 1'000'000);
        h.time_status = o.time_status;
    } else {
        h.time_status = kTimeUnknown;
    }
    return h;
}

}  // namespace

std::vector<std::uint8_t> NovatelEncoder::bestpos(const nav::NavSample& s) {
    const auto body = pack(bestpos_from(s, options_.undulation_m));
    return frame_long(long_header(options_, kBestPosId, s), body);
}

std::vector<std::uint8_t> NovatelEncoder::inspvax(const nav::NavSample& s) {
    const auto body = pack(inspvax_from(s, options_.undulation_m));
    return frame_long(long_header(options_, kInsPvaXId, s), body);
}

std::vector<std::uint8_t> NovatelEncoder::inspvas(const nav::NavSample& s) {
    InsPvaS m = inspvas_from(s, options_.undulation_m);
    if (!s.has(nav::NavSample::kTime)) {
        m.week = 0;  // week 0: "no time" for the decoder
        m.seconds_of_week = 0.0;
    }
    ShortHeader h;
    h.message_id = kInsPvaSId;
    h.week = static_cast<std::uint16_t>(m.week);
    if (s.has(nav::NavSample::kTime))
        h.ms_of_week = static_cast<std::uint32_t>(core::to_week_time(s.t).ns_of_week / 1'000'000);
    return frame_short(h, pack(m));
}

}  // namespace mirage::novatel
