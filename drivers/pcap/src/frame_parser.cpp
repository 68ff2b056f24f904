// SPDX-License-Identifier: Apache-2.0
#include "frame_parser.hpp"

#include <pcap/dlt.h>

#include <algorithm>

namespace mirage::pcap::detail {
namespace {

constexpr std::uint16_t kEtherIpv4 = 0x0800;
constexpr std::uint16_t kEtherIpv6 = 0x86dd;
constexpr std::uint16_t kEtherVlan = 0x8100;
constexpr std::uint16_t kEtherQinQ = 0x88a8;
constexpr std::uint8_t kProtoUdp = 17;

std::uint16_t be16(const std::uint8_t* p) { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }
std::uint32_t be32(const std::uint8_t* p) {
    return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
           p[3];
}

// Too few captured bytes: the capture's fault (snaplen) or the frame's (lying header).
FrameStatus short_status(std::size_t caplen, std::uint32_t wire_len) {
    return caplen < wire_len ? FrameStatus::Truncated : FrameStatus::BadHeader;
}

// Finds the network-layer start and its ethertype; false when the link header is cut.
bool link_layer(int dlt, std::span<const std::uint8_t> f, std::size_t& offset,
                std::uint16_t& ethertype) {
    switch (dlt) {
        case DLT_EN10MB: {
            if (f.size() < 14) return false;
            offset = 14;
            ethertype = be16(&f[12]);
            // Up to two tags (802.1ad outer + 802.1Q inner); each adds 4 bytes before the type.
            for (int tags = 0; tags < 2 && (ethertype == kEtherVlan || ethertype == kEtherQinQ);
                 ++tags) {
                if (f.size() < offset + 4) return false;
                ethertype = be16(&f[offset + 2]);
                offset += 4;
            }
            return true;
        }
        case DLT_LINUX_SLL:  // 16-byte cooked header, protocol at 14
            if (f.size() < 16) return false;
            offset = 16;
            ethertype = be16(&f[14]);
            return true;
        case DLT_LINUX_SLL2:  // 20-byte cooked v2 header, protocol at 0
            if (f.size() < 20) return false;
            offset = 20;
            ethertype = be16(&f[0]);
            return true;
        case DLT_NULL: {  // BSD loopback: host-order address family; AF_INET is 2 everywhere
            if (f.size() < 4) return false;
            offset = 4;
            // AF_INET6 differs per OS: 10 (Linux), 24 (NetBSD/OpenBSD), 28 (FreeBSD), 30 (macOS).
            const std::uint8_t af = f[0] != 0 ? f[0] : f[3];
            ethertype = af == 2                                          ? kEtherIpv4
                        : (af == 10 || af == 24 || af == 28 || af == 30) ? kEtherIpv6
                                                                         : 0;
            return true;
        }
        case DLT_IPV6:
            offset = 0;
            ethertype = kEtherIpv6;
            return true;
        default: {  // DLT_RAW / DLT_IPV4: the frame is the IP packet; its version says which
            offset = 0;
            const int version = f.empty() ? 0 : f[0] >> 4;
            ethertype = version == 4 ? kEtherIpv4 : version == 6 ? kEtherIpv6 : 0;
            return true;
        }
    }
}

FrameStatus parse_ipv6(std::span<const std::uint8_t> ip, std::size_t caplen, std::uint32_t wire_len,
                       Ipv4Packet& out) {
    if (ip.size() < 40) return short_status(caplen, wire_len);
    if ((ip[0] >> 4) != 6) return FrameStatus::BadHeader;
    const std::size_t total_len = 40 + std::size_t{be16(&ip[4])};
    if (total_len == 40 && be16(&ip[4]) == 0 && ip[6] == 0) return FrameStatus::BadHeader;  // jumbo
    if (ip.size() < total_len) return short_status(caplen, wire_len);
    out.v6 = true;
    std::copy_n(&ip[8], 16, out.src6.begin());
    std::copy_n(&ip[24], 16, out.dst6.begin());
    std::uint8_t next = ip[6];
    std::size_t off = 40;
    // Extension headers (RFC 8200 §4): hop-by-hop, routing, destination options, fragment, AH.
    // After a fragment header the rest is the fragment's piece of the fragmentable part.
    out.more_fragments = false;
    out.fragment_offset = 0;
    for (int hops = 0; hops < 16; ++hops) {
        if (next != 0 && next != 43 && next != 60 && next != 44 && next != 51) break;
        if (total_len < off + 8) return FrameStatus::BadHeader;
        if (next == 44) {
            const std::uint16_t fo = be16(&ip[off + 2]);
            next = ip[off];
            off += 8;
            if ((fo & 0xfff8) == 0 && (fo & 1) == 0) continue;  // atomic (RFC 6946)
            out.fragment_offset = fo & 0xfff8u;                 // 8-byte units in bits 15..3
            out.more_fragments = (fo & 1) != 0;
            out.id = be32(&ip[off - 4]);
            break;
        }
        const std::size_t len =
            next == 51 ? (std::size_t{ip[off + 1]} + 2) * 4 : (std::size_t{ip[off + 1]} + 1) * 8;
        next = ip[off];
        off += len;
        if (off > total_len) return FrameStatus::BadHeader;
    }
    out.protocol = next;
    out.payload = ip.subspan(off, total_len - off);
    return next == kProtoUdp ? FrameStatus::Ok : FrameStatus::NotUdp;
}

}  // namespace

bool supported_dlt(int dlt) {
    switch (dlt) {
        case DLT_EN10MB:
        case DLT_LINUX_SLL:
        case DLT_LINUX_SLL2:
        case DLT_NULL:
        case DLT_RAW:
        case DLT_IPV4:
        case DLT_IPV6:
            return true;
        default:
            return false;
    }
}

FrameStatus parse_ipv4_frame(int dlt, std::span<const std::uint8_t> frame, std::uint32_t wire_len,
                             Ipv4Packet& out) {
    std::size_t off = 0;
    std::uint16_t ethertype = 0;
    if (!link_layer(dlt, frame, off, ethertype)) return short_status(frame.size(), wire_len);
    if (ethertype == kEtherIpv6) return parse_ipv6(frame.subspan(off), frame.size(), wire_len, out);
    if (ethertype != kEtherIpv4) return FrameStatus::NotIpv4;

    const auto ip = frame.subspan(off);
    if (ip.size() < 20) return short_status(frame.size(), wire_len);
    if ((ip[0] >> 4) != 4) return FrameStatus::BadHeader;
    const std::size_t header_len = static_cast<std::size_t>(ip[0] & 0x0f) * 4;
    if (header_len < 20) return FrameStatus::BadHeader;
    std::size_t total_len = be16(&ip[2]);
    // Total length 0: a TSO/GSO super-packet captured on the sending host; the frame is the packet.
    if (total_len == 0 && frame.size() == wire_len) total_len = ip.size();
    if (total_len < header_len) return FrameStatus::BadHeader;
    if (ip.size() < header_len) return short_status(frame.size(), wire_len);
    if (ip.size() < total_len) return short_status(frame.size(), wire_len);

    std::copy_n(&ip[12], 4, out.src.begin());
    std::copy_n(&ip[16], 4, out.dst.begin());
    out.id = be16(&ip[4]);
    out.protocol = ip[9];
    const std::uint16_t flags_offset = be16(&ip[6]);
    out.more_fragments = (flags_offset & 0x2000) != 0;
    out.fragment_offset = static_cast<std::uint32_t>(flags_offset & 0x1fff) * 8;
    out.payload = ip.subspan(header_len, total_len - header_len);
    if (out.protocol != kProtoUdp) return FrameStatus::NotUdp;
    return FrameStatus::Ok;
}

FrameStatus parse_udp(std::span<const std::uint8_t> ip_payload, UdpDatagram& out) {
    if (ip_payload.size() < 8) return FrameStatus::BadHeader;
    const std::size_t udp_len = be16(&ip_payload[4]);
    // A UDP length shorter than the IP payload is legal (trailing bytes are ignored, as Linux
    // does); longer, or shorter than its own header, is not.
    if (udp_len < 8 || udp_len > ip_payload.size()) return FrameStatus::BadHeader;
    out.src.port = be16(&ip_payload[0]);
    out.dst.port = be16(&ip_payload[2]);
    out.payload.assign(ip_payload.begin() + 8,
                       ip_payload.begin() + static_cast<std::ptrdiff_t>(udp_len));
    return FrameStatus::Ok;
}

}  // namespace mirage::pcap::detail
