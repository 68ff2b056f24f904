// SPDX-License-Identifier: Apache-2.0
#pragma once
// Input of fuzz_pcap_frame, shared with the seed generator: byte 0 picks the link type from
// kFuzzLinkTypes; then records of u16 LE length, a step byte (bits 0-6: capture time since the
// previous frame in 0.5 s units, so the 30 s reassembly timeout is reachable; bit 7: the capture
// cut the frame, its wire length is 64 bytes more) and the frame's bytes.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace mirage::pcap::test {

// libpcap DLT_* numbers: Ethernet, Linux SLL, SLL2, BSD loopback, raw IP, IPv4, IPv6, and one
// the parser does not support (802.11).
inline constexpr std::array<int, 8> kFuzzLinkTypes{1, 113, 276, 0, 12, 228, 229, 105};

struct FuzzFrame {
    std::span<const std::uint8_t> bytes;
    std::uint32_t wire_len = 0;
    std::int64_t time_ns = 0;
};

template <class Fn>
void for_each_frame(std::span<const std::uint8_t> in, Fn&& fn) {
    std::int64_t t = 1'700'000'000'000'000'000;
    std::size_t at = 0;
    while (at + 3 <= in.size()) {
        const std::size_t len = in[at] | std::size_t{in[at + 1]} << 8;
        const std::uint8_t step = in[at + 2];
        at += 3;
        const std::size_t n = len < in.size() - at ? len : in.size() - at;
        t += std::int64_t{step & 0x7F} * 500'000'000;
        const auto cut = (step & 0x80) != 0 ? 64u : 0u;
        fn(FuzzFrame{in.subspan(at, n), static_cast<std::uint32_t>(n) + cut, t});
        at += n;
    }
}

inline void append_frame(std::vector<std::uint8_t>& out, const std::vector<std::uint8_t>& frame,
                         std::uint8_t step) {
    out.push_back(static_cast<std::uint8_t>(frame.size()));
    out.push_back(static_cast<std::uint8_t>(frame.size() >> 8));
    out.push_back(step);
    for (const auto b : frame) out.push_back(b);
}

}  // namespace mirage::pcap::test
