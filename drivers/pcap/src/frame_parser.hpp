// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <span>

#include "mirage/pcap/pcap.hpp"

namespace mirage::pcap::detail {

// One IPv4 packet cut out of a captured frame; `payload` is bounded by the IP total length
// (Ethernet padding removed) and points into the frame.
struct Ipv4Packet {
    std::array<std::uint8_t, 4> src{}, dst{};
    bool v6 = false;  // an IPv6 packet: addresses in src6 / dst6, never a fragment here
    std::array<std::uint8_t, 16> src6{}, dst6{};
    std::uint16_t id = 0;
    std::uint8_t protocol = 0;
    bool more_fragments = false;
    std::uint32_t fragment_offset = 0;  // bytes
    std::span<const std::uint8_t> payload;
    bool is_fragment() const { return more_fragments || fragment_offset != 0; }
};

// Link layer (libpcap DLT_*) + IPv4 or IPv6 header (IPv6 extension headers are skipped; an IPv6
// fragment other than an atomic one is FrameStatus::Fragment). `wire_len` is the frame's original length: a
// header that runs past the captured bytes is Truncated when the capture cut the frame
// (caplen < wire_len), BadHeader when the frame itself is too short for what it claims.
bool supported_dlt(int dlt);
FrameStatus parse_ipv4_frame(int dlt, std::span<const std::uint8_t> frame, std::uint32_t wire_len,
                             Ipv4Packet& out);

// UDP header of a whole (unfragmented or reassembled) IP payload. Fills ports and payload.
FrameStatus parse_udp(std::span<const std::uint8_t> ip_payload, UdpDatagram& out);

}  // namespace mirage::pcap::detail
