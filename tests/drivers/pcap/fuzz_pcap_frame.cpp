// SPDX-License-Identifier: Apache-2.0
// libFuzzer: captured frames (fuzz_pcap_frame.hpp) through the link/IP parser, IPv4 and IPv6
// fragment reassembly and the UDP parser, in the order the pcap reader applies them. A
// reassembled datagram must fit its IP version and a UDP payload its IP payload.
#include "fuzz_pcap_frame.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

#include "frame_parser.hpp"
#include "ip_reassembler.hpp"

using namespace mirage::pcap;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const int dlt = test::kFuzzLinkTypes[data[0] % test::kFuzzLinkTypes.size()];
    if (!detail::supported_dlt(dlt)) return 0;
    detail::IpReassembler reassembler;
    test::for_each_frame({data + 1, size - 1}, [&](const test::FuzzFrame& f) {
        if (reassembler.pending() != 0) reassembler.expire(f.time_ns);
        detail::Ipv4Packet ip;
        if (detail::parse_ipv4_frame(dlt, f.bytes, f.wire_len, ip) != FrameStatus::Ok) return;
        if (ip.payload.size() > f.bytes.size()) __builtin_trap();
        std::vector<std::uint8_t> whole;
        std::span<const std::uint8_t> payload = ip.payload;
        if (ip.is_fragment()) {
            std::uint64_t frames = 0;
            if (reassembler.add(ip, f.time_ns, whole, frames) !=
                detail::IpReassembler::Result::Complete)
                return;
            if (whole.size() > detail::IpReassembler::max_datagram(ip.v6) || frames < 2)
                __builtin_trap();
            payload = whole;
        }
        UdpDatagram d;
        if (detail::parse_udp(payload, d) == FrameStatus::Ok &&
            d.payload.size() + 8 > payload.size())
            __builtin_trap();
    });
    reassembler.drain();
    (void)reassembler.take_abandoned();
    if (reassembler.pending() != 0) __builtin_trap();
    return 0;
}
