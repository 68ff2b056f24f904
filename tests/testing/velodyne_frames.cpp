// SPDX-License-Identifier: Apache-2.0
#include "velodyne_frames.hpp"

#include <cmath>

#include "mirage/velodyne/sensor_clock.hpp"

namespace mirage::velodyne {

FrameAssembler::FrameAssembler(const ModelDescriptor* expected, FrameFn on_frame)
    : expected_(expected), on_frame_(std::move(on_frame)) {}

DecodeStatus FrameAssembler::add(std::span<const std::uint8_t> bytes) {
    const DecodeStatus s = decode_data(bytes, expected_, scratch_);
    counters_.add(s);
    if (s == DecodeStatus::Ok) add(scratch_);
    return s;
}

void FrameAssembler::close(bool ends_at_wrap) {
    if (cur_.packets > 0 || !cur_.points.empty()) {
        cur_.complete = cur_started_at_wrap_ && ends_at_wrap && !cur_has_gap_;
        ++stats_.frames;
        if (on_frame_) on_frame_(cur_);
    }
    cur_ = Frame{};
    cur_started_at_wrap_ = ends_at_wrap;
    cur_has_gap_ = false;
}

void FrameAssembler::add(const DecodedPacket& p) {
    ++stats_.packets;
    const ModelDescriptor& md = *p.model;
    if (have_prev_) {
        const double period_us = static_cast<double>(md.packet_period_ns(p.mode)) / 1000.0;
        const std::uint32_t dt = (p.timestamp_us + kMicrosPerHour - prev_ts_) % kMicrosPerHour;
        if (static_cast<double>(dt) > 1.5 * period_us || dt == 0) {
            ++stats_.gaps;
            // Backwards or duplicate packets count as a gap of zero missing packets.
            if (dt < kMicrosPerHour / 2 && dt > 0)
                stats_.missing_packets +=
                    static_cast<std::uint64_t>(std::llround(dt / period_us)) - 1;
            cur_has_gap_ = true;
            close(false);
            prev_az_ = -1;
        }
    }
    have_prev_ = true;
    prev_ts_ = p.timestamp_us;
    for (int b = 0; b < kBlocksPerPacket; ++b) {
        const int az = p.block_azimuth[static_cast<std::size_t>(b)];
        if (prev_az_ >= 0 && az < prev_az_) close(true);
        if (cur_.packets == 0 && cur_.points.empty()) cur_.first_timestamp_us = p.timestamp_us;
        prev_az_ = az;
        for (int c = 0; c < kSlotsPerBlock; ++c) {
            const Firing& f = p.firing[static_cast<std::size_t>(kSlotsPerBlock * b + c)];
            if (f.raw_distance != 0) cur_.points.push_back(f);
        }
    }
    ++cur_.packets;
}

void FrameAssembler::flush() { close(false); }

}  // namespace mirage::velodyne
