// SPDX-License-Identifier: Apache-2.0
// Pieces of `mirage stream-bench` that match received packets to their schedule.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

namespace mirage::hil {

// 64-bit fingerprint of a packet's bytes (8 bytes per step, then a final mix): consecutive packets
// differ in their timestamps, azimuths or CRC, so the fingerprint identifies a packet among
// those in flight. Cheap enough for 25 kB Ouster packets at full rate.
inline std::uint64_t packet_key(std::span<const std::uint8_t> bytes) {
    constexpr std::uint64_t kMul = 0x9E3779B97F4A7C15ull;
    std::uint64_t h = bytes.size() * kMul;
    std::size_t i = 0;
    for (; i + 8 <= bytes.size(); i += 8) {
        std::uint64_t w;
        std::memcpy(&w, bytes.data() + i, 8);
        h = (h ^ w) * kMul;
        h ^= h >> 29;
    }
    std::uint64_t tail = 0;
    std::memcpy(&tail, bytes.data() + i, bytes.size() - i);
    h = (h ^ tail) * kMul;
    h ^= h >> 32;
    return h;
}

// What the sending side knows about a packet when it hands it to the output.
struct ScheduledPacket {
    std::uint64_t key = 0;
    std::int64_t deadline_ns = 0;  // CLOCK_MONOTONIC instant the schedule puts it on the wire
    bool data = false;             // lidar data (not position / IMU)
};

// Single-producer single-consumer ring: the render writer thread pushes each packet before it is
// sent, the receiver thread finds it by key. Packets arrive in order over loopback, so the
// receiver scans forward from its read position; entries it skips are packets it never got.
class ScheduleRing {
  public:
    explicit ScheduleRing(std::size_t capacity_pow2 = std::size_t{1} << 17)
        : slots_(capacity_pow2), mask_(capacity_pow2 - 1) {}

    // Producer. False when full (the receiver is that far behind): the packet goes unrecorded.
    bool push(const ScheduledPacket& p) {
        const std::uint64_t head = head_.load(std::memory_order_relaxed);
        if (head - tail_.load(std::memory_order_acquire) >= slots_.size()) return false;
        slots_[head & mask_] = p;
        head_.store(head + 1, std::memory_order_release);
        return true;
    }

    // Consumer: the first entry with `key` among the next `lookahead` ones; entries before it
    // are dropped and counted in `skipped`. False (nothing consumed) when no entry matches.
    bool match(std::uint64_t key, ScheduledPacket& out, std::uint64_t& skipped,
               std::size_t lookahead = 8192) {
        const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
        const std::uint64_t head = head_.load(std::memory_order_acquire);
        const std::uint64_t end = std::min<std::uint64_t>(head, tail + lookahead);
        for (std::uint64_t i = tail; i < end; ++i) {
            if (slots_[i & mask_].key != key) continue;
            out = slots_[i & mask_];
            skipped += i - tail;
            tail_.store(i + 1, std::memory_order_release);
            return true;
        }
        return false;
    }

  private:
    std::vector<ScheduledPacket> slots_;
    std::uint64_t mask_;
    alignas(64) std::atomic<std::uint64_t> head_{0};
    alignas(64) std::atomic<std::uint64_t> tail_{0};
};

// Exact order statistics of a series of lateness samples (ns), plus drift: least of the last
// tenth − least of the first tenth (delays only add lateness, so each least is the clock relation).
struct LatenessSummary {
    std::uint64_t count = 0;
    std::int64_t p50 = 0, p99 = 0, max = 0, min = 0, drift = 0;
};

inline LatenessSummary summarize(const std::vector<std::int64_t>& series) {
    LatenessSummary s;
    s.count = series.size();
    if (series.empty()) return s;
    const std::size_t tenth = std::max<std::size_t>(1, series.size() / 10);
    const std::int64_t head =
        *std::min_element(series.begin(), series.begin() + static_cast<std::ptrdiff_t>(tenth));
    const std::int64_t tail =
        *std::min_element(series.end() - static_cast<std::ptrdiff_t>(tenth), series.end());
    s.drift = tail - head;
    std::vector<std::int64_t> v = series;
    std::sort(v.begin(), v.end());
    const auto at = [&](double q) {
        const auto i = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
        return v[std::min(i, v.size() - 1)];
    };
    s.p50 = at(0.50);
    s.p99 = at(0.99);
    s.max = v.back();
    s.min = v.front();
    return s;
}

}  // namespace mirage::hil
