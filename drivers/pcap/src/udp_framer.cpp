// SPDX-License-Identifier: Apache-2.0
#include "udp_framer.hpp"

#include <algorithm>

namespace mirage::pcap::detail {
namespace {

constexpr std::size_t kEth = 14, kIp = 20, kUdp = 8, kMinFrame = 60;

void put16(std::uint8_t* p, std::uint32_t v) {
    p[0] = static_cast<std::uint8_t>(v >> 8);
    p[1] = static_cast<std::uint8_t>(v);
}

std::array<std::uint8_t, 6> dst_mac_for(const FrameOptions& opt, const Endpoint& dst) {
    const auto& ip = dst.ip;
    if (ip == std::array<std::uint8_t, 4>{255, 255, 255, 255})
        return {0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
    if ((ip[0] & 0xf0) == 0xe0)  // 224.0.0.0/4 -> 01:00:5e + low 23 bits (RFC 1112 §6.4)
        return {0x01, 0x00, 0x5e, static_cast<std::uint8_t>(ip[1] & 0x7f), ip[2], ip[3]};
    return opt.dst_mac;
}

}  // namespace

std::uint32_t ones_sum(std::span<const std::uint8_t> bytes, std::uint32_t sum) {
    std::size_t i = 0;
    for (; i + 1 < bytes.size(); i += 2) sum += (std::uint32_t{bytes[i]} << 8) | bytes[i + 1];
    if (i < bytes.size()) sum += std::uint32_t{bytes[i]} << 8;  // odd byte, zero-padded
    while (sum >> 16) sum = (sum & 0xffff) + (sum >> 16);
    return sum;
}

std::uint16_t fold_complement(std::uint32_t sum) {
    while (sum >> 16) sum = (sum & 0xffff) + (sum >> 16);
    return static_cast<std::uint16_t>(~sum & 0xffff);
}

void frame_udp(const FrameOptions& opt, const Endpoint& src, const Endpoint& dst,
               std::uint16_t ip_id, std::span<const std::uint8_t> payload, std::size_t mtu,
               std::vector<std::uint8_t>& frame,
               const std::function<void(std::span<const std::uint8_t>)>& emit) {
    const std::size_t udp_len = kUdp + payload.size();
    std::array<std::uint8_t, kUdp> udp{};
    put16(&udp[0], src.port);
    put16(&udp[2], dst.port);
    put16(&udp[4], static_cast<std::uint32_t>(udp_len));
    if (opt.udp_checksum) {
        // Pseudo-header (RFC 768): src, dst, zero, protocol, UDP length.
        std::uint32_t sum = ones_sum(src.ip);
        sum = ones_sum(dst.ip, sum);
        sum += 17 + static_cast<std::uint32_t>(udp_len);
        sum = ones_sum(udp, sum);
        sum = ones_sum(payload, sum);
        const std::uint16_t c = fold_complement(sum);
        put16(&udp[6], c == 0 ? 0xffff : c);  // 0 would mean "no checksum"
    }

    const auto mac = dst_mac_for(opt, dst);
    // Per-fragment IP payload: the largest multiple of 8 that fits the MTU (1480 for 1500).
    const std::size_t piece = ((mtu - kIp) / 8) * 8;
    const bool fragmented = udp_len > mtu - kIp;
    std::size_t offset = 0;  // into the IP payload = UDP header + payload
    do {
        const std::size_t len = std::min(piece, udp_len - offset);
        const bool more = offset + len < udp_len;
        frame.assign(std::max(kEth + kIp + len, kMinFrame), 0);
        std::uint8_t* f = frame.data();
        std::copy(mac.begin(), mac.end(), f);
        std::copy(opt.src_mac.begin(), opt.src_mac.end(), f + 6);
        put16(f + 12, 0x0800);
        std::uint8_t* ip = f + kEth;
        ip[0] = 0x45;
        put16(ip + 2, static_cast<std::uint32_t>(kIp + len));
        put16(ip + 4, ip_id);
        // Linux sets DF (path-MTU discovery) on datagrams it does not have to fragment.
        const std::uint32_t flags = fragmented ? (more ? 0x2000u : 0u) : 0x4000u;
        put16(ip + 6, flags | static_cast<std::uint32_t>(offset / 8));
        ip[8] = opt.ttl;
        ip[9] = 17;
        std::copy(src.ip.begin(), src.ip.end(), ip + 12);
        std::copy(dst.ip.begin(), dst.ip.end(), ip + 16);
        put16(ip + 10, fold_complement(ones_sum({ip, kIp})));
        // Copy this piece of (UDP header ++ payload).
        std::uint8_t* out = ip + kIp;
        std::size_t i = offset;
        const std::size_t end = offset + len;
        if (i < kUdp) {
            const std::size_t n = std::min(end, kUdp) - i;
            out = std::copy_n(udp.begin() + static_cast<std::ptrdiff_t>(i), n, out);
            i += n;
        }
        if (end > i)
            std::copy_n(payload.begin() + static_cast<std::ptrdiff_t>(i - kUdp), end - i, out);
        emit(frame);
        offset += len;
    } while (offset < udp_len);
}

void frame_udp6(const FrameOptions& opt, const Endpoint& src, const Endpoint& dst,
                std::span<const std::uint8_t> payload, std::vector<std::uint8_t>& frame) {
    constexpr std::size_t kIp6 = 40;
    const std::size_t udp_len = kUdp + payload.size();
    frame.assign(std::max(kEth + kIp6 + udp_len, kMinFrame), 0);
    std::uint8_t* f = frame.data();
    std::copy(opt.dst_mac.begin(), opt.dst_mac.end(), f);
    std::copy(opt.src_mac.begin(), opt.src_mac.end(), f + 6);
    put16(f + 12, 0x86dd);
    std::uint8_t* ip = f + kEth;
    ip[0] = 0x60;
    put16(ip + 4, static_cast<std::uint32_t>(udp_len));
    ip[6] = 17;
    ip[7] = opt.ttl;
    std::copy(src.ip6.begin(), src.ip6.end(), ip + 8);
    std::copy(dst.ip6.begin(), dst.ip6.end(), ip + 24);
    std::uint8_t* udp = ip + kIp6;
    put16(udp, src.port);
    put16(udp + 2, dst.port);
    put16(udp + 4, static_cast<std::uint32_t>(udp_len));
    std::copy(payload.begin(), payload.end(), udp + kUdp);
    // Pseudo-header: source, destination, upper-layer length, next header (UDP).
    std::uint32_t sum = ones_sum(src.ip6);
    sum = ones_sum(dst.ip6, sum);
    sum += static_cast<std::uint32_t>(udp_len >> 16) + static_cast<std::uint32_t>(udp_len & 0xffff);
    sum += 17;
    sum = ones_sum({udp, udp_len}, sum);
    const std::uint16_t c = fold_complement(sum);
    put16(udp + 6, c == 0 ? 0xffff : c);  // IPv6 forbids a zero UDP checksum
}

}  // namespace mirage::pcap::detail
