// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "frame_parser.hpp"

namespace mirage::pcap::detail {

// IP fragment reassembly keyed by (version, src, dst, id, protocol), as RFC 791 (IPv4) and
// RFC 8200 §4.5 (IPv6) define and Linux does. Pieces may arrive in any order and overlap (later
// bytes win). Incomplete datagrams are given up after
// kTimeoutNs of capture time (Linux ipfrag_time) or when more than kMaxPending are open.
class IpReassembler {
  public:
    static constexpr std::int64_t kTimeoutNs = 30'000'000'000;
    static constexpr std::size_t kMaxPending = 256;
    static constexpr std::uint32_t kMaxDatagram = 65535 - 20;  // largest IPv4 payload
    static constexpr std::uint32_t kMaxDatagram6 = 65535;      // largest IPv6 fragmentable part
    static constexpr std::uint32_t max_datagram(bool v6) {
        return v6 ? kMaxDatagram6 : kMaxDatagram;
    }

    enum class Result { Pending, Complete, Bad };

    // Adds one fragment. Complete: `payload` holds the whole IP payload and `frames` how many
    // frames it took. Bad: the fragment is inconsistent (beyond 64 KiB, unaligned middle piece,
    // conflicting end) and was dropped on its own.
    Result add(const Ipv4Packet& p, std::int64_t time_ns, std::vector<std::uint8_t>& payload,
               std::uint64_t& frames);
    // Gives up datagrams older than the timeout at `now_ns`.
    void expire(std::int64_t now_ns);
    // Gives up everything (end of capture).
    void drain();
    // Frames of given-up datagrams since the last call (they end as FrameStatus::Fragment).
    std::uint64_t take_abandoned() { return std::exchange(abandoned_, 0); }
    std::size_t pending() const { return pending_.size(); }

  private:
    struct Pending {
        std::vector<std::uint8_t> data;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> pieces;  // [begin, end)
        std::int64_t first_time_ns = 0;
        std::int64_t total = -1;  // known once the last piece (MF = 0) arrived
        std::uint64_t frames = 0;
    };
    // version, protocol, id (4 bytes), source (16), destination (16); IPv4 addresses in the
    // first 4 bytes of each.
    using Key = std::array<std::uint8_t, 38>;
    static Key key_of(const Ipv4Packet& p);
    static bool complete(Pending& d);
    void evict_oldest();

    std::map<Key, Pending> pending_;
    std::uint64_t abandoned_ = 0;
};

}  // namespace mirage::pcap::detail
