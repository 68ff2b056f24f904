// SPDX-License-Identifier: Apache-2.0
// Coincidence processing (docs/photon-counting.md §5) on simulated gates: nadir gates over one
// cell, a ground return of known mean under noise, first events drawn exactly. Coates' correction
// recovers the return's mean and the noise rate; a leaf over the ground needs more gates before
// the ground comes out, as the Poisson law says; noise alone gives no points.
#include "mirage/render/coincidence.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "mirage/core/error.hpp"
#include "mirage/core/rng.hpp"
#include "mirage/physics/geiger.hpp"

namespace mirage::render {
namespace {

constexpr double kBin = 0.25;       // m, height and range bins alike (nadir)
constexpr double kTop = 100.0;      // the gate opens at this height
constexpr std::size_t kBins = 400;  // and spans 100 m

// `gates` nadir gates over the cell at (0.1, 0.1): bin k spans heights kTop − k·kBin down; the
// returns (height, mean events) fall in their bins; noise per bin on top. Each gate's first event.
CoincidenceGrid collect_grid(std::uint64_t gates, std::vector<std::pair<double, double>> returns,
                             double noise, std::uint64_t seed, double false_alarm = 1e-6,
                             std::optional<CoincidenceWindow> window = {},
                             std::uint64_t first_gate = 0, bool dwells = false) {
    std::vector<double> signal(kBins, 0.0);
    for (const auto& [z, n] : returns) signal[static_cast<std::size_t>((kTop - z) / kBin)] += n;
    const physics::EventRate rate(signal, noise, kBin);
    CoincidenceGrid grid({1.0, kBin, 3, false_alarm, 0, window, 0, dwells});
    std::vector<physics::GeigerEvent> ev;
    for (std::uint64_t g = first_gate; g < first_gate + gates; ++g) {
        core::PulseRng rng(seed, g, 0);
        physics::geiger_events(rate, {{1e9, false}}, rng, 1, ev);
        const Gate gate{{0.1, 0.1, kTop + 1000.0}, {0, 0, -1}, 1000.0, 1000.0 + kBins * kBin};
        if (ev.empty()) {
            grid.add(gate, nullptr);
            continue;
        }
        // The event's height: kTop − t·(kBin per bin); nudged inside its bin.
        const double z = kTop - ev[0].t_ns * (kBin / kBin) - 1e-9;
        GateEvent e{0.1, 0.1, z,
                    ev[0].kind == physics::EventKind::Signal ? std::uint8_t(2) : std::uint8_t(1),
                    ev[0].kind == physics::EventKind::Signal};
        grid.add(gate, &e);
    }
    return grid;
}

std::vector<CoincidencePoint> collect(std::uint64_t gates,
                                      std::vector<std::pair<double, double>> returns, double noise,
                                      std::uint64_t seed, CoincidenceStats* st,
                                      double false_alarm = 1e-6) {
    return collect_grid(gates, std::move(returns), noise, seed, false_alarm).finish(st);
}

TEST(Coincidence, coates_recovers_the_return_and_the_noise) {
    CoincidenceStats st;
    const auto pts = collect(20000, {{40.1, 0.5}}, 0.002, 1, &st);
    ASSERT_EQ(pts.size(), 1u);
    const auto& p = pts[0];
    std::printf(
        "20000 gates: one point at z %.3f (bin 40.00-40.25), expected events %.4f "
        "(0.5 + noise 0.002), %u events of %u armed gates; noise %.5f per gate-bin "
        "(0.002); signal share %.3f\n",
        p.z, p.expected, p.events, p.gates, st.noise_per_bin, p.signal_share);
    EXPECT_NEAR(p.expected, 0.502, 0.502 * 0.03);
    EXPECT_NEAR(st.noise_per_bin, 0.002, 0.002 * 0.05);
    EXPECT_GE(p.z, 40.0);
    EXPECT_LT(p.z, 40.25);
    EXPECT_EQ(p.classification, 2);
    EXPECT_EQ(st.gates, 20000u);
}

// A dwell of n gates per cell is the collection's first n gates there: one grid of 20000 gates
// finished at 5000 gives exactly what a collection of 5000 gives (the same first 5000 gates).
TEST(Coincidence, a_dwell_counts_the_first_gates_of_each_cell) {
    CoincidenceStats all, dwell, short_run;
    // A grid made for dwells against collections counted without one (the alone one).
    const CoincidenceGrid grid = collect_grid(20000, {{40.1, 0.5}}, 0.002, 1, 1e-6, {}, 0, true);
    const auto full = grid.finish(&all);
    const auto part = grid.finish(&dwell, 5000);
    const auto alone = collect(5000, {{40.1, 0.5}}, 0.002, 1, &short_run);
    ASSERT_EQ(full.size(), 1u);
    ASSERT_EQ(part.size(), alone.size());
    ASSERT_EQ(part.size(), 1u);
    EXPECT_EQ(part[0].z, alone[0].z);
    EXPECT_EQ(part[0].expected, alone[0].expected);
    EXPECT_EQ(part[0].events, alone[0].events);
    EXPECT_EQ(part[0].gates, alone[0].gates);
    EXPECT_EQ(dwell.gates, 5000u);
    EXPECT_EQ(dwell.events, short_run.events);
    EXPECT_EQ(dwell.noise_per_bin, short_run.noise_per_bin);
    EXPECT_EQ(all.gates, 20000u);
    EXPECT_GT(full[0].events, 3 * part[0].events);
    // A window that leaves the cell out leaves no gate.
    CoincidenceStats none;
    EXPECT_TRUE(collect_grid(100, {{40.1, 0.5}}, 0.002, 1, 1e-6, CoincidenceWindow{1, 1, 2, 2})
                    .finish(&none)
                    .empty());
    EXPECT_EQ(none.gates, 0u);
}

// Threads fill grids of consecutive gates and append them: the same as one grid of all gates.
TEST(Coincidence, appended_grids_equal_one_grid_of_all_their_gates) {
    for (const bool dwells : {false, true}) {
        CoincidenceStats one, two;
        const auto whole =
            collect_grid(20000, {{40.1, 0.5}, {45.1, 0.3}}, 0.002, 7, 1e-6, {}, 0, dwells)
                .finish(&one);
        CoincidenceGrid first =
            collect_grid(8000, {{40.1, 0.5}, {45.1, 0.3}}, 0.002, 7, 1e-6, {}, 0, dwells);
        first.append(
            collect_grid(12000, {{40.1, 0.5}, {45.1, 0.3}}, 0.002, 7, 1e-6, {}, 8000, dwells));
        const auto joined = first.finish(&two, 0);
        ASSERT_EQ(whole.size(), 2u);
        ASSERT_EQ(joined.size(), whole.size());
        for (std::size_t k = 0; k < whole.size(); ++k) {
            EXPECT_EQ(joined[k].z, whole[k].z);
            EXPECT_EQ(joined[k].expected, whole[k].expected);
            EXPECT_EQ(joined[k].events, whole[k].events);
        }
        EXPECT_EQ(two.gates, one.gates);
        EXPECT_EQ(two.events, one.events);
        EXPECT_EQ(two.noise_per_bin, one.noise_per_bin);
        if (!dwells) {  // counts alone cannot answer a dwell
            EXPECT_THROW(first.finish(nullptr, 10000), Error);
            continue;
        }
        // And a dwell over the joined grid reaches into the appended gates in order.
        CoincidenceStats d;
        first.finish(&d, 10000);
        EXPECT_EQ(d.gates, 10000u);
    }
}

// The armed gates and events of every event bin, against a direct count over the gates: gates
// opening within a few bins of each other (counted by bin), and half of them spread over
// kilometres (listed), with and without a dwell, from a grid keeping every gate and from one
// keeping counts. Every bin with an event stands out here (min_events 1, a false-alarm
// probability near 1), so each point is one bin to check.
TEST(Coincidence, armed_gates_and_events_match_a_direct_count) {
    for (const double spread : {1.0, 5000.0}) {
        for (const bool dwells : {false, true}) {
            const double bin = 0.25;
            CoincidenceGrid grid({1.0, bin, 1, 1.0 - 1e-9, 0, {}, 0, dwells});
            struct G {
                std::int64_t top, bottom, stop;
                bool fired;
            };
            std::vector<G> gates;
            core::PulseRng rng(42, static_cast<std::uint64_t>(spread), 0);
            for (int k = 0; k < 400; ++k) {
                // The gate opens here: the first half within a metre, the rest over the spread
                // (counts by bin that turn into a list).
                const double z0 = 1000.0 + (k < 200 ? 1.0 : spread) * rng.uniform();
                const double length = 100.0 + spread;  // so the gates overlap
                const Gate gate{{0.3, 0.6, z0 + 50.0}, {0, 0, -1}, 50.0, 50.0 + length};
                G g{std::int64_t(std::floor(z0 / bin)),
                    std::int64_t(std::floor((z0 - length) / bin)), 0, rng.uniform() < 0.6};
                g.stop = g.bottom;
                if (g.fired) {
                    // Events fall on 7 depths into the gate, so bins gather several; those near
                    // its ends lie among the other gates' ends.
                    constexpr double kDepth[7] = {1e-6, 0.002, 0.25, 0.5, 0.75, 0.998, 1.0 - 1e-6};
                    const double z = z0 - length * kDepth[std::size_t(7.0 * rng.uniform())];
                    const GateEvent e{0.3, 0.6, z, 2, true};
                    g.stop = std::int64_t(std::floor(z / bin));
                    grid.add(gate, &e);
                } else {
                    grid.add(gate, nullptr);
                }
                gates.push_back(g);
            }
            for (const std::uint32_t dwell : {0u, 150u}) {
                if (dwell && !dwells) continue;
                const std::size_t n = dwell ? dwell : gates.size();
                const auto pts = grid.finish(nullptr, dwell);
                std::size_t bins_with_armed_gates = 0;
                std::vector<std::int64_t> seen;
                for (std::size_t i = 0; i < n; ++i)
                    if (gates[i].fired) seen.push_back(gates[i].stop);
                std::sort(seen.begin(), seen.end());
                seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
                for (const std::int64_t b : seen) {
                    std::int64_t events = 0, covering = 0, above = 0;
                    for (std::size_t i = 0; i < n; ++i) {
                        const G& g = gates[i];
                        events += g.fired && g.stop == b;
                        above += g.fired && g.stop > b;
                        covering += g.bottom <= b && b <= g.top;
                    }
                    const std::int64_t armed = std::max<std::int64_t>(covering - above, 0);
                    if (armed == 0) continue;
                    ++bins_with_armed_gates;
                    const auto p = std::find_if(pts.begin(), pts.end(), [&](const auto& q) {
                        return std::int64_t(std::floor(q.z / bin)) == b;
                    });
                    ASSERT_NE(p, pts.end()) << "spread " << spread << " bin " << b;
                    EXPECT_EQ(p->events, std::uint32_t(events))
                        << "spread " << spread << " bin " << b;
                    EXPECT_EQ(p->gates, std::uint32_t(armed))
                        << "spread " << spread << " bin " << b;
                    EXPECT_NEAR(p->x, 0.3, 1e-6);
                    EXPECT_NEAR(p->y, 0.6, 1e-6);
                }
                EXPECT_EQ(pts.size(), bins_with_armed_gates) << "spread " << spread;
                EXPECT_GT(bins_with_armed_gates, 5u);
            }
        }
    }
}

// Gates over 48 × 48 cells of 0.5 m, taken in turn (so consecutive gates fall in different
// cells), each cell with a surface of its own height (cell x − cell y, ± 20 m): every cell gives
// one point, at its own height and inside itself, whatever order the cells were first met in and
// whether the gates went into one grid or two appended ones.
TEST(Coincidence, every_cell_keeps_its_own_gates) {
    constexpr int kSide = 48;
    constexpr double kCell = 0.5;
    const auto height = [](int cx, int cy) { return 0.05 + 0.25 * double(cx - cy); };
    const auto fill = [&](CoincidenceGrid& grid, int from, int to) {
        for (int k = from; k < to; ++k) {
            const int cell = (k * 7919) % (kSide * kSide);  // a scattered order, every cell
            const int cx = cell % kSide - kSide / 2, cy = cell / kSide - kSide / 2;
            const double x = (cx + 0.3) * kCell, y = (cy + 0.6) * kCell;
            const Gate gate{{x, y, 100.0}, {0, 0, -1}, 50.0, 150.0};
            const GateEvent e{x, y, height(cx, cy), 2, true};
            grid.add(gate, k >= 5 * kSide * kSide ? nullptr : &e);  // a sixth round, none
        }
    };
    const int gates = 6 * kSide * kSide;
    for (const bool dwells : {false, true}) {
        const CoincidenceParams p{kCell, kBin, 3, 1e-6, 0, {}, 0, dwells};
        CoincidenceGrid one(p), two(p), later(p);
        fill(one, 0, gates);
        fill(two, 0, gates / 3);
        fill(later, gates / 3, gates);
        two.append(std::move(later));
        for (CoincidenceGrid* grid : {&one, &two}) {
            CoincidenceStats st;
            const auto pts = grid->finish(&st);
            EXPECT_EQ(st.cells, std::uint64_t(kSide * kSide));
            ASSERT_EQ(pts.size(), std::size_t(kSide * kSide)) << "dwells " << dwells;
            for (const auto& q : pts) {
                const int cx = int(std::floor(q.x / kCell)), cy = int(std::floor(q.y / kCell));
                EXPECT_NEAR(q.x, (cx + 0.3) * kCell, 1e-6);
                EXPECT_NEAR(q.y, (cy + 0.6) * kCell, 1e-6);
                EXPECT_NEAR(q.z, height(cx, cy), 1e-6) << "cell " << cx << ", " << cy;
                EXPECT_EQ(q.events, 5u);
            }
        }
    }
}

// One bin's point from events of three classes at known places: the mean of their positions, the
// most frequent class (3 and 5 tie: the lower), the share flagged signal; the same to the last
// bit whether the grid keeps every gate or sums, and whether it was filled whole or in two parts.
TEST(Coincidence, a_point_is_the_mean_of_its_events_and_their_most_frequent_class) {
    struct E {
        double x, y, z;
        std::uint8_t cls;
        bool signal;
    };
    const E events[] = {{0.11, 0.42, 40.02, 5, true},
                        {0.37, 0.05, 40.13, 3, true},
                        {0.29, 0.33, 40.07, 1, false},
                        {0.02, 0.48, 40.11, 5, false},
                        {0.45, 0.21, 40.01, 3, true}};
    const auto fill = [&](CoincidenceGrid& grid, int from, int to) {
        for (int k = from; k < to; ++k) {
            const Gate gate{{0.25, 0.25, kTop + 1000.0}, {0, 0, -1}, 1000.0, 1000.0 + kBins * kBin};
            const E& e = events[k % 5];
            const GateEvent ev{e.x, e.y, e.z, e.cls, e.signal};
            grid.add(gate, k < 10 ? &ev : nullptr);  // each event twice, then 30 empty gates
        }
    };
    std::vector<CoincidencePoint> seen;
    for (const bool dwells : {false, true}) {
        const CoincidenceParams p{1.0, kBin, 3, 1e-6, 0, {}, 0, dwells};
        CoincidenceGrid whole(p), part(p), later(p);
        fill(whole, 0, 40);
        fill(part, 0, 3);
        fill(later, 3, 40);
        part.append(std::move(later));
        for (CoincidenceGrid* grid : {&whole, &part}) {
            const auto pts = grid->finish();
            ASSERT_EQ(pts.size(), 1u);
            seen.push_back(pts[0]);
        }
    }
    const CoincidencePoint& q = seen[0];
    EXPECT_NEAR(q.x, (0.11 + 0.37 + 0.29 + 0.02 + 0.45) / 5, 1e-7);
    EXPECT_NEAR(q.y, (0.42 + 0.05 + 0.33 + 0.48 + 0.21) / 5, 1e-7);
    EXPECT_NEAR(q.z, (40.02 + 40.13 + 40.07 + 40.11 + 40.01) / 5, 1e-7);
    EXPECT_EQ(q.events, 10u);
    EXPECT_EQ(q.classification, 3);
    EXPECT_DOUBLE_EQ(q.signal_share, 0.6);
    for (const CoincidencePoint& o : seen) {
        EXPECT_EQ(o.x, q.x);
        EXPECT_EQ(o.y, q.y);
        EXPECT_EQ(o.z, q.z);
        EXPECT_EQ(o.expected, q.expected);
        EXPECT_EQ(o.classification, q.classification);
        EXPECT_EQ(o.signal_share, q.signal_share);
    }
}

// Slanted gates over negative and positive cells, a window, events on four surfaces and in noise
// of six classes: gates added one at a time or in batches of 37 (the vectorised path), to a grid
// keeping every gate or summing, give the same points to the bit. Every bin with an event stands
// out (min_events 1, a false-alarm probability near 1), so every sum is checked.
TEST(Coincidence, batches_and_modes_give_the_same_points) {
    struct In {
        Gate gate;
        GateEvent event;
        bool fired;
    };
    std::vector<In> in;
    core::PulseRng rng(5, 0, 0);
    for (int k = 0; k < 6000; ++k) {
        const Eigen::Vector3d origin(-20.0 + 25.0 * rng.uniform(), -5.0 + 25.0 * rng.uniform(),
                                     500);
        const Eigen::Vector3d dir =
            Eigen::Vector3d(0.04 * rng.uniform() - 0.02, 0.04 * rng.uniform() - 0.02, -1)
                .normalized();
        const double r = rng.uniform() < 0.8 ? 500.0 - 10.0 * std::floor(4.0 * rng.uniform())
                                             : 450.0 + 110.0 * rng.uniform();
        const Eigen::Vector3d at = origin + r * dir;
        const auto cls = static_cast<std::uint8_t>(1 + std::floor(6.0 * rng.uniform()));
        in.push_back({{origin, dir, 450.0, 560.0},
                      {at.x(), at.y(), at.z(), cls, cls == 2},
                      rng.uniform() < 0.7});
    }
    std::vector<std::vector<CoincidencePoint>> got;
    for (const bool dwells : {false, true}) {
        for (const std::size_t batch : {std::size_t(1), std::size_t(37)}) {
            CoincidenceGrid grid({0.5, 0.15, 1, 1.0 - 1e-9, 0,
                                  CoincidenceWindow{-25.0, -12.0, 8.0, 22.0}, 0, dwells});
            for (std::size_t k = 0; k < in.size(); k += batch) {
                const std::size_t n = std::min(batch, in.size() - k);
                std::vector<double> o[3], d[3];
                std::vector<const GateEvent*> first;
                for (std::size_t i = k; i < k + n; ++i) {
                    for (int a = 0; a < 3; ++a) {
                        o[a].push_back(in[i].gate.origin[a]);
                        d[a].push_back(in[i].gate.dir[a]);
                    }
                    first.push_back(in[i].fired ? &in[i].event : nullptr);
                }
                if (batch == 1)
                    grid.add(in[k].gate, first[0]);
                else
                    grid.add({o[0], o[1], o[2], d[0], d[1], d[2], 450.0, 560.0}, first);
            }
            CoincidenceStats st;
            got.push_back(grid.finish(&st));
            EXPECT_LT(st.gates, in.size());  // the window left some out
            EXPECT_GT(st.cells, 1000u);
        }
    }
    ASSERT_GT(got[0].size(), 1000u);
    for (const auto& pts : got) {
        ASSERT_EQ(pts.size(), got[0].size());
        for (std::size_t k = 0; k < pts.size(); ++k) {
            const CoincidencePoint &a = pts[k], &b = got[0][k];
            EXPECT_TRUE(a.x == b.x && a.y == b.y && a.z == b.z && a.events == b.events &&
                        a.gates == b.gates && a.classification == b.classification &&
                        a.signal_share == b.signal_share)
                << "point " << k;
        }
    }
}

// A gate or an event that is not finite or too far out, a gate looking up, and lines shorter than
// the batch are refused before anything is added.
TEST(Coincidence, bad_gates_are_refused) {
    CoincidenceGrid grid({});
    const GateEvent fine{0, 0, 10, 1, false}, nan{0, std::nan(""), 10, 1, false};
    const Gate down{{0, 0, 100}, {0, 0, -1}, 10, 100};
    EXPECT_THROW(grid.add(Gate{{0, 0, 100}, {0, 0, 1}, 10, 100}, nullptr), ConfigError);
    EXPECT_THROW(grid.add(Gate{{std::nan(""), 0, 100}, {0, 0, -1}, 10, 100}, nullptr), ConfigError);
    EXPECT_THROW(grid.add(down, &nan), ConfigError);
    // Finite, but a cell index past 2^62 (its integer would overflow).
    EXPECT_THROW(grid.add(Gate{{1e30, 0, 100}, {0, 0, -1}, 10, 100}, nullptr), ConfigError);
    const std::vector<double> one{0.0};
    const std::vector<const GateEvent*> two{&fine, nullptr};
    EXPECT_THROW(grid.add({one, one, one, one, one, one, 10, 100}, two), Error);
    CoincidenceStats st;
    EXPECT_TRUE(grid.finish(&st).empty());
    EXPECT_EQ(st.gates, 0u);
    grid.add(down, &fine);
    grid.finish(&st);
    EXPECT_EQ(st.gates, 1u);
}

TEST(Coincidence, noise_alone_gives_no_point) {
    CoincidenceStats st;
    EXPECT_TRUE(collect(20000, {}, 0.002, 2, &st).empty());
    EXPECT_GT(st.events, 10000u);
}

// A leaf (0.5 events) 5 m over the ground (2 events): the ground's first events come in
// e^(−0.5)(1 − e^(−2)) = 0.524 of the gates less what the noise above blocks, and a bin needs 3
// events; with a false-alarm
// probability (1e-3) that the faint noise (5e-4 per bin) never decides, the share of collections
// where the ground comes out is the binomial tail P(≥ 3 of n), rising with the gates (the seed's
// 60/240/480-pulse dwell).
TEST(Coincidence, more_gates_bring_out_what_lies_under_a_leaf) {
    double seen[3] = {};
    const std::uint64_t gates[3] = {2, 4, 8};
    for (int g = 0; g < 3; ++g) {
        int ground = 0;
        for (std::uint64_t trial = 0; trial < 400; ++trial) {
            const auto pts =
                collect(gates[g], {{45.1, 0.5}, {40.1, 2.0}}, 0.0005, 100 + trial, nullptr, 1e-3);
            for (const auto& p : pts) ground += p.z < 41.0;
        }
        seen[g] = ground / 400.0;
    }
    // At least 3 of n gates fire in the ground's bin: binomial tail with p = e^(−0.5 − 239·5e-4)
    // ·(1 − e^(−2 − 5e-4)) = 0.4653 (the noise in the 239 bins above blocks it too).
    const auto at_least3 = [](int n) {
        const double p = std::exp(-0.5 - 239 * 0.0005) * -std::expm1(-2.0 - 0.0005);
        double below = 0;
        for (int k = 0; k < 3; ++k)
            below += std::tgamma(n + 1) / (std::tgamma(k + 1) * std::tgamma(n - k + 1)) *
                     std::pow(p, k) * std::pow(1 - p, n - k);
        return 1 - below;
    };
    std::printf(
        "ground found over 400 collections: 2 gates %.3f, 4 gates %.3f (%.3f), 8 gates "
        "%.3f (%.3f)\n",
        seen[0], seen[1], at_least3(4), seen[2], at_least3(8));
    EXPECT_EQ(seen[0], 0.0);
    EXPECT_NEAR(seen[1], at_least3(4), 0.06);
    EXPECT_NEAR(seen[2], at_least3(8), 0.04);
}

}  // namespace
}  // namespace mirage::render
