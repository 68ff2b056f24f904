// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "mirage/pcap/writer.hpp"

namespace mirage::pcap::detail {

// RFC 1071 one's-complement sum, folded; callers complement it.
std::uint32_t ones_sum(std::span<const std::uint8_t> bytes, std::uint32_t sum = 0);
std::uint16_t fold_complement(std::uint32_t sum);

// Builds the Ethernet frames of one UDP datagram (one, or several IP fragments for payloads over
// mtu - 28) into `frame` and calls `emit` with each. payload.size() <= Writer::kMaxPayload.
void frame_udp(const FrameOptions& opt, const Endpoint& src, const Endpoint& dst,
               std::uint16_t ip_id, std::span<const std::uint8_t> payload, std::size_t mtu,
               std::vector<std::uint8_t>& frame,
               const std::function<void(std::span<const std::uint8_t>)>& emit);

// One Ethernet/IPv6/UDP frame of a whole datagram (addresses in src.ip6 / dst.ip6, UDP checksum
// over the RFC 8200 §8.1 pseudo-header): the BPF filter's view of a reassembled IPv6 datagram.
// 8 + payload.size() <= 65535.
void frame_udp6(const FrameOptions& opt, const Endpoint& src, const Endpoint& dst,
                std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& frame);

}  // namespace mirage::pcap::detail
