// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace mirage::pcap {

// Contract (lead): implemented with libpcap. Ethernet II (optionally one 802.1Q tag) or Linux
// cooked (SLL) link layers, IPv4, UDP. IP fragments are reassembled when all pieces are present.

struct Endpoint {
    std::array<std::uint8_t, 4> ip{127, 0, 0, 1};
    std::uint16_t port = 0;
};

// One UDP datagram of a capture. time_ns: capture timestamp, ns since the Unix epoch.
struct UdpDatagram {
    std::int64_t time_ns = 0;
    Endpoint src, dst;
    std::vector<std::uint8_t> payload;
};

// Why a frame was not a usable UDP datagram; counted by the reader, never thrown.
enum class FrameStatus : std::uint8_t {
    Ok,
    Truncated,  // caplen < what the headers say
    NotIpv4,    // other ethertype (ARP, IPv6, ...)
    NotUdp,     // other IP protocol
    BadHeader,  // IHL < 5, total length inconsistent, UDP length inconsistent
    Fragment,   // a fragment still waiting for its other pieces
};
inline constexpr std::size_t kFrameStatusCount = 6;

// Reads UDP datagrams from a classic pcap or pcapng file (µs or ns precision).
class Reader {
  public:
    explicit Reader(const std::string& path);  // throws IoError naming the file
    ~Reader();
    Reader(const Reader&) = delete;
    Reader& operator=(const Reader&) = delete;
    // Next UDP datagram; false at end of file. Frames that are not UDP are skipped and counted.
    bool next(UdpDatagram& out);
    // Frames seen with each status, indexed by FrameStatus. The frames of a reassembled datagram
    // count as Ok; those of a datagram never completed count as Fragment once given up (30 s of
    // capture time, or at the end of the file), so after next() returned false the counts add
    // up to the number of frames in the file.
    const std::array<std::uint64_t, kFrameStatusCount>& counts() const { return counts_; }
    std::uint64_t count(FrameStatus s) const { return counts_[static_cast<std::size_t>(s)]; }
    // Why reading stopped before a clean end of file (e.g. a record cut by a full disk or a
    // crash: libpcap's message); empty otherwise. The cut record is counted as Truncated.
    const std::string& error() const;

  private:
    struct Impl;
    Impl* impl_;
    std::array<std::uint64_t, kFrameStatusCount> counts_{};
};

// Convenience: all UDP datagrams of a file, optionally only those to one destination port (0: all).
std::vector<UdpDatagram> read_udp(const std::string& path, std::uint16_t dst_port = 0);

}  // namespace mirage::pcap
