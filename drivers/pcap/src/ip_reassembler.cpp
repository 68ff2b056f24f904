// SPDX-License-Identifier: Apache-2.0
#include "ip_reassembler.hpp"

#include <algorithm>

namespace mirage::pcap::detail {
IpReassembler::Key IpReassembler::key_of(const Ipv4Packet& p) {
    Key k{};
    k[0] = p.v6 ? 6 : 4;
    k[1] = p.protocol;
    for (int i = 0; i < 4; ++i) k[2 + i] = static_cast<std::uint8_t>(p.id >> (24 - 8 * i));
    if (p.v6) {
        std::copy(p.src6.begin(), p.src6.end(), k.begin() + 6);
        std::copy(p.dst6.begin(), p.dst6.end(), k.begin() + 22);
    } else {
        std::copy(p.src.begin(), p.src.end(), k.begin() + 6);
        std::copy(p.dst.begin(), p.dst.end(), k.begin() + 22);
    }
    return k;
}

IpReassembler::Result IpReassembler::add(const Ipv4Packet& p, std::int64_t time_ns,
                                         std::vector<std::uint8_t>& payload,
                                         std::uint64_t& frames) {
    const auto begin = p.fragment_offset;
    const auto len = static_cast<std::uint32_t>(p.payload.size());
    const std::uint32_t end = begin + len;
    // Every piece but the last carries a multiple of 8 bytes (RFC 791, RFC 8200 §4.5); nothing
    // ends past 64 KiB.
    if (end > max_datagram(p.v6) || (p.more_fragments && (len == 0 || len % 8 != 0)))
        return Result::Bad;

    const Key key = key_of(p);
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
