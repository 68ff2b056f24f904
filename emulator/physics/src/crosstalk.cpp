// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/crosstalk.hpp"

#include <algorithm>
#include <cmath>

namespace mirage::physics {

// uniform_of_word(w) < probability ⟺ w + ½ < probability·2³² (both sides exact) ⟺ w below
// ⌈probability·2³² − ½⌉, an integer up to 2³².
void crosstalk_fires(const std::array<const std::uint32_t*, 4>& words, double probability,
                     std::uint32_t columns, std::uint32_t pixels, std::uint8_t* out) {
    const double x = std::ceil(std::clamp(probability, 0.0, 1.0) * 0x1p32 - 0.5);
    const auto below = static_cast<std::uint64_t>(std::max(0.0, x));
    for (std::uint32_t row0 = 0; row0 < pixels; row0 += columns) {
        const std::uint32_t end = std::min(pixels - row0, columns);
        for (std::uint32_t c = 0; c < end; ++c) {
            const std::uint32_t p = row0 + c;
            const bool left = c > 0, right = c + 1 < end, up = row0 > 0,
                       down = std::uint64_t(p) + columns < pixels;
            out[p] = static_cast<std::uint8_t>((left && words[0][p] < below ? kFireLeft : 0) |
                                               (right && words[1][p] < below ? kFireRight : 0) |
                                               (up && words[2][p] < below ? kFireUp : 0) |
                                               (down && words[3][p] < below ? kFireDown : 0));
        }
    }
}

// Each pixel starts from its own event (none if it is dead then); the pixels that fire anything
// pass their times on in increasing order of time (a detection's time is final when it is the
// least left: only an earlier one could lower it), each to the neighbours that would take it
// (armed, and earlier than what they hold). So every pixel ends with the least time over the chains
// of firings that reach it armed: what the time-ordered pass keeps (docs/photon-counting.md §2).
void crosstalk_first_events(std::span<GeigerEvent> kept, std::span<const double> armed,
                            std::span<const std::uint8_t> fires, std::uint32_t columns,
                            std::vector<CrosstalkFiring>& heap) {
    const auto n = static_cast<std::uint32_t>(kept.size());
    const auto later = [](const CrosstalkFiring& a, const CrosstalkFiring& b) {
        return b.t_ns < a.t_ns;
    };
    heap.clear();
    for (std::uint32_t p = 0; p < n; ++p) {
        if (!(kept[p].t_ns >= armed[p])) kept[p].t_ns = INFINITY;  // dead: lost
        if (fires[p] != 0 && std::isfinite(kept[p].t_ns)) heap.push_back({kept[p].t_ns, p});
    }
    std::make_heap(heap.begin(), heap.end(), later);
    const std::int64_t step[4] = {-1, 1, -std::int64_t(columns), std::int64_t(columns)};
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), later);
        const auto [t, p] = heap.back();
        heap.pop_back();
        if (t != kept[p].t_ns) continue;  // it was taken earlier since
        for (int s = 0; s < 4; ++s) {
            if (!(fires[p] & (1u << s))) continue;
            const auto q = static_cast<std::uint32_t>(std::int64_t(p) + step[s]);
            if (!(t < kept[q].t_ns) || !(t >= armed[q])) continue;
            kept[q] = {t, EventKind::Crosstalk};
            if (fires[q] != 0) {
                heap.push_back({t, q});
                std::push_heap(heap.begin(), heap.end(), later);
            }
        }
    }
}

}  // namespace mirage::physics
