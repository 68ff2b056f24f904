// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "mirage/nav/nav_sample.hpp"
#include "mirage/ncom/packet.hpp"

namespace mirage::ncom {

struct EncoderOptions {
    // Status channels sent in turn, one per packet. Channel 0 (time, satellites, modes) must
    // come at least every 5th packet; other channels carry an all-zero payload (Mirage has no
    // innovations or GNSS receiver counters to report).
    std::vector<std::uint8_t> channels{0, 1, 2};
};

// Fake-INS NCOM encoder. NavSample -> packet: time rounded to the nearest ms (GPS minute +
// ms), lat/lon degrees -> radians, heading in (−π, π], i24 fields rounded to nearest; fields
// the sample lacks are written as 0x800000 (invalid). FixQuality -> nav status 4 (locked) and
// position mode (None -> nav status 2 "initialising"). Throws ConfigError on a channel list
// that leaves more than 4 packets between channel-0 packets.
class NcomEncoder {
  public:
    explicit NcomEncoder(EncoderOptions options = {});

    std::array<std::uint8_t, kPacketSize> encode(const nav::NavSample& s);
    // The Packet encode() would pack (for tests and tools).
    Packet to_packet(const nav::NavSample& s, std::uint8_t channel) const;

    std::uint64_t packets() const { return count_; }

  private:
    EncoderOptions options_;
    std::uint64_t count_ = 0;
};

std::uint8_t position_mode_for(nav::FixQuality q);
// Quality of a locked solution from channel 0's position mode.
nav::FixQuality quality_from_position_mode(std::uint8_t mode);

}  // namespace mirage::ncom
