// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace mirage::pcap {

// Contract (lead): implemented with libpcap. Ethernet II (up to two 802.1Q / 802.1ad tags), Linux
// cooked (SLL, SLL2), BSD loopback or raw IP link layers; IPv4 and IPv6 (extension headers
// skipped); UDP. IPv4 fragments are reassembled when all pieces are present; IPv6 fragments are
// not (counted as Fragment). Classic pcap and pcapng (one link type per file, a libpcap limit).

struct Endpoint {
    std::array<std::uint8_t, 4> ip{127, 0, 0, 1};
    std::uint16_t port = 0;
    // IPv6 datagrams: v6 is set, ip6 holds the address and ip stays 0.0.0.0.
    bool v6 = false;
    std::array<std::uint8_t, 16> ip6{};
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
    NotIpv4,    // not an IP packet: other ethertype (ARP, ...), or an unsupported link type
    NotUdp,     // other IP protocol
    BadHeader,  // IHL < 5, total length inconsistent, UDP length inconsistent; a capture time
                // beyond int64 ns since 1970 (years 1970..2262)
    Fragment,   // a fragment still waiting for its other pieces (or any IPv6 fragment)
};
inline constexpr std::size_t kFrameStatusCount = 6;

// Short name of a status for summaries ("truncated", "not-ip", ...).
const char* to_string(FrameStatus s);

struct ReaderOptions {
    // true: a file whose link type the reader cannot parse throws IoError in the constructor;
    // false: it opens, and every frame counts as NotIpv4 (see Reader::link_supported()).
    bool unknown_link_throws = true;
};

// Reads UDP datagrams from a classic pcap or pcapng file (µs or ns precision).
class Reader {
  public:
    explicit Reader(const std::string& path);  // throws IoError naming the file
    Reader(const std::string& path, const ReaderOptions& options);
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
    // File offset of the record where reading stopped on an error (-1 when none): the first
    // byte that is not part of a whole record.
    std::int64_t error_offset() const;
    // File offset at which the record of the datagram last returned by next() starts (of its
    // last frame, for a reassembled datagram).
    std::int64_t record_offset() const;

    // Keeps only frames matching a libpcap filter expression (pcap-filter(7), e.g.
    // "udp dst port 2368 and host 192.168.1.201"), compiled for the file's link type. A
    // reassembled IPv4 datagram is tested as one unfragmented Ethernet/IPv4/UDP frame, so port
    // filters match every fragment. Throws ConfigError naming the file and the expression.
    void set_filter(const std::string& expression);
    // Frames / reassembled datagrams the filter rejected (not included in counts()).
    std::uint64_t filtered() const;
    int link_type() const;
    bool link_supported() const;
    const std::string& path() const;

  private:
    struct Impl;
    Impl* impl_;
    std::array<std::uint64_t, kFrameStatusCount> counts_{};
};

// Convenience: all UDP datagrams of a file, optionally only those to one destination port (0: all).
std::vector<UdpDatagram> read_udp(const std::string& path, std::uint16_t dst_port = 0);

}  // namespace mirage::pcap
