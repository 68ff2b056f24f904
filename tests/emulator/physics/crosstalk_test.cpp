// SPDX-License-Identifier: Apache-2.0
// Crosstalk of first events in closed form (docs/photon-counting.md §2) against a detector's own
// rule, played out here event by event in time order: random frames with ties, dead pixels and
// chains of firings, compared pixel by pixel.
#include "mirage/physics/crosstalk.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <tuple>
#include <vector>

namespace {

using mirage::physics::crosstalk_fires;
using mirage::physics::crosstalk_first_events;
using mirage::physics::EventKind;
using mirage::physics::GeigerEvent;

// The rule for one pixel p, written on the uniforms: direction s (left, right, up, down) fires
// when its word's uniform lies below the probability and the neighbour is in the frame.
std::uint8_t one_pixel_fires(const std::uint32_t words[4], double probability, std::uint32_t p,
                             std::uint32_t columns, std::uint32_t pixels) {
    const std::uint32_t col = p % columns, row = p / columns;
    const bool inside[4] = {col > 0, col + 1 < columns && p + 1 < pixels, row > 0,
                            std::uint64_t(p) + columns < pixels};
    std::uint8_t out = 0;
    for (int s = 0; s < 4; ++s)
        if (inside[s] && mirage::core::uniform_of_word(words[s]) < probability)
            out = static_cast<std::uint8_t>(out | (1u << s));
    return out;
}

// Pixel p's firings from crosstalk_fires over a whole frame whose every pixel has `words`.
std::uint8_t frame_fires(const std::uint32_t words[4], double probability, std::uint32_t p,
                         std::uint32_t columns, std::uint32_t pixels) {
    std::array<std::vector<std::uint32_t>, 4> w;
    for (int s = 0; s < 4; ++s) w[s].assign(pixels, words[s]);
    std::vector<std::uint8_t> out(pixels);
    crosstalk_fires({w[0].data(), w[1].data(), w[2].data(), w[3].data()}, probability, columns,
                    pixels, out.data());
    return out[p];
}

// Events in time order (ties: by pixel, then the order they were made, own ones first); an event
// is kept if its pixel is armed and has detected nothing yet, and then fires its neighbours at
// the same time.
std::vector<GeigerEvent> time_ordered(const std::vector<GeigerEvent>& own,
                                      const std::vector<double>& armed,
                                      const std::vector<std::uint8_t>& fires, std::uint32_t columns,
                                      std::size_t& ties) {
    using Queued = std::tuple<double, std::uint32_t, std::uint32_t, EventKind>;  // t, p, seq
    std::vector<Queued> queue;
    std::uint32_t seq = 0;
    for (std::uint32_t p = 0; p < own.size(); ++p)
        if (std::isfinite(own[p].t_ns)) queue.emplace_back(own[p].t_ns, p, seq++, own[p].kind);
    std::vector<GeigerEvent> kept(own.size(), {INFINITY, EventKind::Noise});
    const std::int64_t step[4] = {-1, 1, -std::int64_t(columns), std::int64_t(columns)};
    while (!queue.empty()) {
        const auto it = std::min_element(queue.begin(), queue.end());
        const auto [t, p, s, kind] = *it;
        queue.erase(it);
        ties += kind == EventKind::Crosstalk && kept[p].t_ns == t && kept[p].kind != kind;
        if (t < armed[p] || std::isfinite(kept[p].t_ns)) continue;
        kept[p] = {t, kind};
        for (int d = 0; d < 4; ++d)
            if (fires[p] & (1u << d))
                queue.emplace_back(t, std::uint32_t(std::int64_t(p) + step[d]), seq++,
                                   EventKind::Crosstalk);
    }
    return kept;
}

TEST(Crosstalk, fires_only_neighbours_inside_the_frame_below_the_probability) {
    const std::uint32_t low[4] = {0, 0, 0, 0};
    const std::uint32_t high[4] = {~0u, ~0u, ~0u, ~0u};
    EXPECT_EQ(frame_fires(high, 0.5, 5, 4, 16), 0);
    EXPECT_EQ(frame_fires(low, 0.5, 5, 4, 16), 15);     // inside: all four
    EXPECT_EQ(frame_fires(low, 0.5, 0, 4, 16), 2 | 8);  // corner: right, down
    EXPECT_EQ(frame_fires(low, 0.5, 15, 4, 16), 1 | 4);
    EXPECT_EQ(frame_fires(low, 0.5, 6, 4, 9), 1 | 2 | 4);  // pixel 10 is not in the frame
    EXPECT_EQ(frame_fires(low, 0.5, 8, 4, 9), 4);          // nor 9
    EXPECT_EQ(frame_fires(low, 0.5, 2, 1, 4), 4 | 8);      // one column
    const std::uint32_t half[4] = {0x7FFFFFFFu, 0x80000000u, 0, ~0u};  // u just below / above ½
    EXPECT_EQ(frame_fires(half, 0.5, 5, 4, 16), 1 | 4);
}

// The frame's at once (compares on the words) as pixel by pixel (on the uniforms): random words,
// and words at the probability's edge.
TEST(Crosstalk, a_frame_fires_as_its_pixels_one_by_one) {
    std::mt19937_64 gen(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int frame = 0; frame < 3000; ++frame) {
        const std::uint32_t columns = 1 + std::uint32_t(gen() % 40),
                            rows = 1 + std::uint32_t(gen() % 40);
        const std::uint32_t n = columns * rows - std::uint32_t(gen() % (columns * rows));
        const double p = frame % 7 == 0 ? 0.0 : frame % 11 == 0 ? 1.0 : u(gen);
        const auto edge = static_cast<std::uint32_t>(
            std::min(4294967295.0, std::max(0.0, std::floor(p * 0x1p32 - 0.5))));
        std::array<std::vector<std::uint32_t>, 4> w;
        for (auto& v : w) {
            v.resize(n);
            for (auto& x : v) {
                const auto r = static_cast<std::uint32_t>(gen());
                x = r % 4 == 0 ? edge + (r >> 2) % 3 - 1 : r;  // near the edge, or anywhere
            }
        }
        std::vector<std::uint8_t> all(n);
        crosstalk_fires({w[0].data(), w[1].data(), w[2].data(), w[3].data()}, p, columns, n,
                        all.data());
        for (std::uint32_t q = 0; q < n; ++q) {
            const std::uint32_t one[4] = {w[0][q], w[1][q], w[2][q], w[3][q]};
            ASSERT_EQ(all[q], one_pixel_fires(one, p, q, columns, n))
                << "frame " << frame << " pixel " << q << " p " << p;
        }
    }
}

// 20 000 random frames up to 8 × 8: own events at a few distinct times (so ties happen), a
// quarter of pixels dead until a random time, firings with probability ½ per neighbour.
TEST(Crosstalk, first_events_in_closed_form_match_the_time_ordered_rule) {
    std::mt19937_64 gen(7);
    std::uniform_int_distribution<std::uint32_t> dim(1, 8), word;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<GeigerEvent> kept;
    std::vector<mirage::physics::CrosstalkFiring> heap;
    std::size_t crosstalk = 0, lost = 0, ties = 0;
    for (int frame = 0; frame < 20000; ++frame) {
        const std::uint32_t columns = dim(gen), rows = dim(gen);
        const std::uint32_t n = columns * rows - (u(gen) < 0.3 ? dim(gen) % (columns * rows) : 0);
        const double p_own = u(gen), p_fire = u(gen);
        std::vector<GeigerEvent> own(n);
        std::vector<double> armed(n, -INFINITY);
        std::vector<std::uint8_t> fires(n);
        for (std::uint32_t p = 0; p < n; ++p) {
            own[p] = u(gen) < p_own ? GeigerEvent{double(dim(gen)), u(gen) < 0.5 ? EventKind::Signal
                                                                                 : EventKind::Noise}
                                    : GeigerEvent{INFINITY, EventKind::Noise};
            if (u(gen) < 0.25) armed[p] = double(dim(gen)) + (u(gen) < 0.5 ? 0.0 : 0.5);
            const std::uint32_t w[4] = {word(gen), word(gen), word(gen), word(gen)};
            fires[p] = one_pixel_fires(w, p_fire, p, columns, n);
        }
        kept = own;
        crosstalk_first_events(kept, armed, fires, columns, heap);
        const auto want = time_ordered(own, armed, fires, columns, ties);
        ASSERT_EQ(kept.size(), n);
        for (std::uint32_t p = 0; p < n; ++p) {
            ASSERT_EQ(kept[p].t_ns, want[p].t_ns) << "frame " << frame << " pixel " << p;
            if (std::isfinite(want[p].t_ns)) {
                ASSERT_EQ(kept[p].kind, want[p].kind) << "frame " << frame << " pixel " << p;
            }
            crosstalk += want[p].kind == EventKind::Crosstalk && std::isfinite(want[p].t_ns);
            lost += std::isfinite(own[p].t_ns) && !(want[p].t_ns == own[p].t_ns);
        }
    }
    std::printf(
        "20000 frames: %zu crosstalk events kept, %zu own events lost, %zu own events that "
        "crosstalk reached at the same time\n",
        crosstalk, lost, ties);
    EXPECT_GT(crosstalk, 10000u);
    EXPECT_GT(lost, 10000u);
    EXPECT_GT(ties, 1000u);
}

}  // namespace
