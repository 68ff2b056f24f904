// SPDX-License-Identifier: Apache-2.0
// Whether a spinning thread's scheduling gaps recur with a fixed period (a timer tick: the guest
// kernel's, CONFIG_HZ, or the hypervisor's), which says where a machine's timing floor comes
// from (mirage-sched-gaps).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "gap_overlap.hpp"

namespace mirage::hil {

struct GapPeriod {
    std::size_t gaps = 0;      // gaps longer than the threshold
    double period_ns = 0;      // most common spacing of their starts (0: fewer than 3 gaps, or
                               // none spaced under 100 ms)
    double spacing_share = 0;  // share of the spacings in its bin and the two beside it
    double phase_share = 0;    // share of the gaps starting within a tenth of the period of one
                               // phase (about 0.1 for gaps at random times)
};

// Starts of the gaps longer than `longer_than` ns: the spacings between successive ones, in 10 µs
// bins up to 100 ms, give the period (the mean of the spacings in the fullest bin and its two
// neighbours); the starts folded modulo that period into 20 phase bins give the share of the
// fullest two adjacent bins.
inline GapPeriod gap_period(const std::vector<Gap>& gaps, std::int64_t longer_than) {
    GapPeriod out;
    std::vector<std::int64_t> starts;
    for (const Gap& g : gaps)
        if (g.end - g.begin > longer_than) starts.push_back(g.begin);
    out.gaps = starts.size();
    if (starts.size() < 3) return out;
    constexpr std::int64_t kBin = 10'000;
    constexpr std::size_t kBins = 10'000;     // 100 ms
    std::vector<std::size_t> hist(kBins, 0);  // spacings per bin
    std::vector<double> sum(kBins, 0.0);      // and their total, ns
    for (std::size_t i = 1; i < starts.size(); ++i) {
        const std::int64_t d = starts[i] - starts[i - 1];
        const auto b = static_cast<std::size_t>(d / kBin);
        if (b >= kBins) continue;
        ++hist[b];
        sum[b] += static_cast<double>(d);
    }
    const auto mode =
        static_cast<std::size_t>(std::max_element(hist.begin(), hist.end()) - hist.begin());
    const std::size_t lo = mode == 0 ? 0 : mode - 1, hi = std::min(kBins, mode + 2);
    std::size_t near = 0;
    double near_sum = 0;
    for (std::size_t b = lo; b < hi; ++b) {
        near += hist[b];
        near_sum += sum[b];
    }
    if (near == 0) return out;  // every spacing over 100 ms: no tick
    const double spacings = static_cast<double>(starts.size() - 1);
    out.period_ns = near_sum / static_cast<double>(near);
    out.spacing_share = static_cast<double>(near) / spacings;
    // Folded a thousand gaps at a time: for a tick that is at most about a thousand periods,
    // over which the period's error (~1e-5 of it) moves the phase by ~1 %; a minute folded at
    // once would smear it over the whole period. And a thousand gaps at random times fill the
    // fullest two of 20 phase bins to only ~12 %.
    constexpr std::size_t kPhases = 20, kWindow = 1000;
    std::size_t at_phase = 0;
    for (std::size_t w = 0; w < starts.size();) {
        std::size_t phase[kPhases] = {};
        const std::int64_t s0 = starts[w];
        // The last window takes the remainder (a handful of gaps alone would fill two bins).
        const std::size_t end = starts.size() - w < 2 * kWindow ? starts.size() : w + kWindow;
        for (std::size_t e = w; e < end; ++e) {
            const double f = std::fmod(static_cast<double>(starts[e] - s0), out.period_ns);
            ++phase[std::min(kPhases - 1, static_cast<std::size_t>(f / out.period_ns * kPhases))];
        }
        std::size_t best = 0;
        for (std::size_t k = 0; k < kPhases; ++k)
            best = std::max(best, phase[k] + phase[(k + 1) % kPhases]);
        at_phase += best;
        w = end;
    }
    out.phase_share = static_cast<double>(at_phase) / static_cast<double>(starts.size());
    return out;
}

}  // namespace mirage::hil
