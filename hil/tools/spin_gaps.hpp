// SPDX-License-Identifier: Apache-2.0
// The machine's floor for real-time work: the gaps a thread that only reads the clock sees
// (mirage-sched-gaps, stream-bench's floor), and the delay distribution of instants they imply.
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "gap_overlap.hpp"
#include "mirage/hostclock/host_clock.hpp"

namespace mirage::hil {

// Spins from `start` to `end` (CLOCK_MONOTONIC ns) reading the clock; returns the gaps over
// 10 µs (a read takes ~20 ns).
inline std::vector<Gap> spin_gaps(std::int64_t start, std::int64_t end) {
    std::vector<Gap> gaps;
    gaps.reserve(1 << 16);
    while (hostclock::monotonic_ns() < start) {
    }
    std::int64_t prev = hostclock::monotonic_ns(), now = prev;
    while ((now = hostclock::monotonic_ns()) < end) {
        if (now - prev > 10'000) gaps.push_back({prev, now});
        prev = now;
    }
    return gaps;
}

// Share of the instants of `span_ns` that a send due then would reach more than `late_ns` late:
// a send due inside a gap waits for its end.
inline double delayed_share(const std::vector<Gap>& gaps, std::int64_t span_ns,
                            std::int64_t late_ns) {
    const std::int64_t t = delayed_for_all(std::span<const std::vector<Gap>>(&gaps, 1), late_ns);
    return span_ns > 0 ? double(t) / double(span_ns) : 0.0;
}

// The delay that a share `q` of instants exceeds (the floor's quantile 1 − q), to 1 µs; 10 µs
// and below are not resolved (the gaps recorded start there).
inline std::int64_t delay_exceeded_by(const std::vector<Gap>& gaps, std::int64_t span_ns,
                                      double q) {
    std::int64_t lo = 10'000, hi = 10'000;
    for (const Gap& g : gaps) hi = std::max(hi, g.end - g.begin);
    if (delayed_share(gaps, span_ns, lo) <= q) return lo;
    while (hi - lo > 1'000) {
        const std::int64_t mid = lo + (hi - lo) / 2;
        (delayed_share(gaps, span_ns, mid) > q ? lo : hi) = mid;
    }
    return hi;
}

}  // namespace mirage::hil
