// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "mirage/velodyne/data_packet.hpp"

namespace mirage::velodyne {

// One revolution of decoded returns (slots with distance 0 are left out).
struct Frame {
    std::vector<Firing> points;
    std::uint32_t first_timestamp_us = 0;
    std::uint64_t packets = 0;
    // Began at an azimuth wrap, ended at the next one, and no packet was missing in between.
    bool complete = false;
};

struct FrameAssemblerStats {
    std::uint64_t packets = 0;          // decoded Ok
    std::uint64_t frames = 0;           // emitted
    std::uint64_t gaps = 0;             // timestamp jumps > 1.5 packet periods (or backwards)
    std::uint64_t missing_packets = 0;  // estimated from the jumps
};

// Splits a stream of data packets into revolutions where a block's azimuth is smaller than the
// previous block's (as ROS/PCL do). A gap in the packet timestamps ends the current frame as
// incomplete and starts a new (incomplete) one, so assembly restarts cleanly at the next wrap.
class FrameAssembler {
  public:
    using FrameFn = std::function<void(const Frame&)>;
    // expected: the model (nullptr: detect from each packet).
    FrameAssembler(const ModelDescriptor* expected, FrameFn on_frame);

    // Decodes and assembles one packet; packets that fail to decode are counted and skipped.
    DecodeStatus add(std::span<const std::uint8_t> bytes);
    void add(const DecodedPacket& packet);
    // Emits the trailing frame (incomplete).
    void flush();

    const FrameAssemblerStats& stats() const { return stats_; }
    const DecodeCounters& decode_counters() const { return counters_; }

  private:
    void close(bool ends_at_wrap);

    const ModelDescriptor* expected_;
    FrameFn on_frame_;
    DecodedPacket scratch_;
    Frame cur_;
    bool cur_started_at_wrap_ = false;
    bool cur_has_gap_ = false;
    bool have_prev_ = false;
    std::uint32_t prev_ts_ = 0;
    int prev_az_ = -1;
    FrameAssemblerStats stats_;
    DecodeCounters counters_;
};

}  // namespace mirage::velodyne
