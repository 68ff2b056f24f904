// SPDX-License-Identifier: Apache-2.0
// Scheduling gaps of spinning threads, and how long every thread at once was held off: whether a
// second sending thread on another CPU could cover for one that lost its CPU (mirage-sched-gaps).
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace mirage::hil {

// Two consecutive clock reads of a spinning thread, ns: it had no CPU in between.
struct Gap {
    std::int64_t begin, end;
};

// Total time (ns) of the instants that every thread would reach more than `late` ns afterwards:
// instants t with, for each thread, a gap where begin ≤ t < end − late. Each thread's gaps are in
// time order and do not overlap (as one thread records them). With one thread this is the sum of
// (end − begin − late) over its gaps longer than `late`.
inline std::int64_t delayed_for_all(std::span<const std::vector<Gap>> gaps, std::int64_t late) {
    if (gaps.empty()) return 0;
    // One thread's delayed instants: [begin, end − late) of each gap longer than `late`.
    const auto delayed = [late](const std::vector<Gap>& g) {
        std::vector<Gap> out;
        for (const Gap& x : g)
            if (x.end - x.begin > late) out.push_back({x.begin, x.end - late});
        return out;
    };
    std::vector<Gap> all = delayed(gaps.front());
    for (std::size_t c = 1; c < gaps.size() && !all.empty(); ++c) {
        const std::vector<Gap> other = delayed(gaps[c]);
        std::vector<Gap> both;
        std::size_t i = 0, j = 0;
        while (i < all.size() && j < other.size()) {
            const std::int64_t lo = std::max(all[i].begin, other[j].begin);
            const std::int64_t hi = std::min(all[i].end, other[j].end);
            if (hi > lo) both.push_back({lo, hi});
            if (all[i].end < other[j].end)
                ++i;
            else
                ++j;
        }
        all = std::move(both);
    }
    std::int64_t total = 0;
    for (const Gap& x : all) total += x.end - x.begin;
    return total;
}

}  // namespace mirage::hil
