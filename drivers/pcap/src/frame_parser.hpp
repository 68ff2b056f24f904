// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <span>

#include "mirage/pcap/pcap.hpp"

namespace mirage::pcap::detail {

// One IP packet cut out of a captured frame; `payload` is bounded by the IP total length
// (Ethernet padding removed) and points into the frame. A fragment (IPv4, or IPv6 with a
// fragment header) carries its offset, more-fragments flag and identification; its payload is
// its piece of the fragmentable part.
struct Ipv4Packet {
    std::array<std::uint8_t, 4> src{}, dst{};
    bool v6 = false;  // an IPv6 packet: addresses in src6 / dst6
    std::array<std::uint8_t, 16> src6{}, dst6{};
    std::uint32_t id = 0;  // IPv4: 16 bits; IPv6: the fragment header's 32 bits
    std::uint8_t protocol = 0;
    bool more_fragments = false;
    std::uint32_t fragment_offset = 0;  // bytes
    std::span<const std::uint8_t> payload;
    bool is_fragment() const { return more_fragments || fragment_offset != 0; }
};

// Link layer (libpcap DLT_*) + IPv4 or IPv6 header (IPv6 extension headers before the fragment
// header are skipped; a fragment's next header is its protocol, and only UDP is reassembled, as
// for IPv4; an atomic fragment, offset 0 without more, is a whole packet). `wire_len` is the
// frame's original length: a header that runs past the captured bytes is Truncated when the capture
// cut the frame (caplen < wire_len), BadHeader when the frame itself is too short for what it
// claims.
bool supported_dlt(int dlt);
FrameStatus parse_ipv4_frame(int dlt, std::span<const std::uint8_t> frame, std::uint32_t wire_len,
                             Ipv4Packet& out);

// UDP header of a whole (unfragmented or reassembled) IP payload. Fills ports and payload.
FrameStatus parse_udp(std::span<const std::uint8_t> ip_payload, UdpDatagram& out);

}  // namespace mirage::pcap::detail
