// SPDX-License-Identifier: Apache-2.0
#include "ip_reassembler.hpp"

#include <algorithm>

namespace mirage::pcap::detail {
namespace {

std::uint32_t be32(const std::array<std::uint8_t, 4>& a) {
    return (std::uint32_t{a[0]} << 24) | (std::uint32_t{a[1]} << 16) | (std::uint32_t{a[2]} << 8) |
           std::uint32_t{a[3]};
}

}  // namespace

IpReassembler::Result IpReassembler::add(const Ipv4Packet& p, std::int64_t time_ns,
                                         std::vector<std::uint8_t>& payload,
                                         std::uint64_t& frames) {
    const auto begin = p.fragment_offset;
    const auto len = static_cast<std::uint32_t>(p.payload.size());
    const std::uint32_t end = begin + len;
    // Every piece but the last carries a multiple of 8 bytes (RFC 791); nothing ends past 64 KiB.
    if (end > kMaxDatagram || (p.more_fragments && (len == 0 || len % 8 != 0))) return Result::Bad;

    const Key key{(std::uint64_t{be32(p.src)} << 32) | be32(p.dst),
                  (std::uint32_t{p.id} << 8) | p.protocol};
    auto it = pending_.find(key);
    if (it == pending_.end()) {
        if (pending_.size() >= kMaxPending) evict_oldest();
        it = pending_.emplace(key, Pending{}).first;
        it->second.first_time_ns = time_ns;
    }
    Pending& d = it->second;
    if (!p.more_fragments) {
        if (d.total >= 0 && d.total != end) return Result::Bad;  // two different ends
        d.total = end;
    }
    if (d.total >= 0 && end > d.total) return Result::Bad;
    if (d.data.size() < end) d.data.resize(end);
    std::copy(p.payload.begin(), p.payload.end(), d.data.begin() + begin);
    d.pieces.emplace_back(begin, end);
    ++d.frames;
    if (!complete(d)) return Result::Pending;

    d.data.resize(static_cast<std::size_t>(d.total));
    payload = std::move(d.data);
    frames = d.frames;
    pending_.erase(it);
    return Result::Complete;
}

bool IpReassembler::complete(Pending& d) {
    if (d.total < 0) return false;
    std::sort(d.pieces.begin(), d.pieces.end());
    std::int64_t covered = 0;
    for (const auto& [b, e] : d.pieces) {
        if (b > covered) return false;  // a hole
        covered = std::max<std::int64_t>(covered, e);
    }
    return covered >= d.total;
}

void IpReassembler::expire(std::int64_t now_ns) {
    for (auto it = pending_.begin(); it != pending_.end();) {
        if (now_ns - it->second.first_time_ns > kTimeoutNs) {
            abandoned_ += it->second.frames;
            it = pending_.erase(it);
        } else {
            ++it;
        }
    }
}

void IpReassembler::evict_oldest() {
    auto oldest = pending_.begin();
    for (auto it = pending_.begin(); it != pending_.end(); ++it)
        if (it->second.first_time_ns < oldest->second.first_time_ns) oldest = it;
    abandoned_ += oldest->second.frames;
    pending_.erase(oldest);
}

void IpReassembler::drain() {
    for (const auto& [key, d] : pending_) abandoned_ += d.frames;
    pending_.clear();
}

}  // namespace mirage::pcap::detail
