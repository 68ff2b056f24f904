// SPDX-License-Identifier: Apache-2.0
// A gated pixel's first event straight from its signal runs (docs/photon-counting.md §2) against
// the EventRate built from the same runs and geiger_events with max_events 1: the same event to
// the bit, over random runs (zero shares, runs cut by the gate's ends, overlaps, no noise) and
// levels, including levels equal to a bin's running sum.
#include "mirage/physics/first_event.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace {

using mirage::core::PulseRng;
using mirage::physics::EventRate;
using mirage::physics::FirstEventResult;
using mirage::physics::GeigerEvent;
using mirage::physics::SignalRun;

TEST(FirstEvent, straight_from_the_runs_equals_the_rate_and_the_draw) {
    std::mt19937_64 gen(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::size_t events = 0, none = 0, undecided = 0, overlapping = 0, rounding = 0;
    for (std::uint64_t pulse = 0; pulse < 200000; ++pulse) {
        const std::size_t bins = 20 + gen() % 200, runs_n = gen() % 4;
        const double noise = u(gen) < 0.2 ? 0.0 : std::pow(10.0, -4.0 * u(gen)) * 0.1;
        const double bin_ns = 0.25, sigma = u(gen) < 0.5 ? 0.0 : 0.3;
        std::vector<std::vector<double>> tables(runs_n), sums(runs_n);
        std::vector<SignalRun> runs;
        std::int64_t k = std::int64_t(gen() % 60) - 20;
        bool overlap = false, opening = false;  // runs overlap; one starts before the gate
        for (std::size_t t = 0; t < runs_n; ++t) {
            auto& w = tables[t];
            w.resize(1 + gen() % 12);
            for (double& v : w) v = u(gen) < 0.15 ? 0.0 : u(gen);
            double sum = 0;
            for (const double v : w) sums[t].push_back(sum += v);
            const double scale = std::pow(10.0, 2.0 * u(gen) - 1.5);
            if (u(gen) < 0.1 && !runs.empty()) {
                k -= std::int64_t(1 + gen() % 3);  // into the previous run
                overlap = true;
            }
            runs.push_back({k, scale, w.data(), sums[t].data(), w.size()});
            opening |= k < 0 && k + std::int64_t(w.size()) > 0;
            k += std::int64_t(w.size() + gen() % 30);
        }
        EventRate rate;
        rate.begin(bins, noise, bin_ns);
        for (const SignalRun& r : runs) rate.add_run(r.k0, r.scale, r.w, r.n);
        rate.finish();
        PulseRng rng(3, pulse, 8), words(3, pulse, 8);
        double level = mirage::physics::first_level(rng);
        const bool boundary = u(gen) < 0.2 && rate.total() > 0;
        if (boundary) {  // on a bin's boundary
            level = rate.level_at(bin_ns * double(gen() % bins));
            if (!(level > 0)) continue;
        }
        std::vector<GeigerEvent> want;
        mirage::physics::geiger_events(rate, {{1e9, false}, sigma}, rng, level, 1, want);
        (void)words.uniform();
        const double u_signal = words.uniform();
        const double jitter = sigma > 0 ? sigma * words.normal() : 0.0;
        GeigerEvent got;
        const auto r =
            mirage::physics::gated_first_event(runs, bins, noise, bin_ns, level, u_signal, got);
        overlapping += overlap;
        if (r == FirstEventResult::Undecided) {
            ++undecided;
            rounding += !overlap && !boundary && !opening;
            continue;
        }
        if (r == FirstEventResult::None) {
            ++none;
            ASSERT_TRUE(want.empty()) << pulse;
            continue;
        }
        ++events;
        ASSERT_EQ(want.size(), 1u) << pulse;
        ASSERT_EQ(got.t_ns + jitter, want[0].t_ns) << pulse;
        ASSERT_EQ(got.kind, want[0].kind) << pulse;
    }
    std::printf(
        "200000 pixels: %zu events, %zu none, %zu undecided (%zu of them at a random level with "
        "runs inside the gate, apart; %zu pixels had overlapping runs)\n",
        events, none, undecided, rounding, overlapping);
    EXPECT_GT(events, 50000u);
    EXPECT_GT(none, 20000u);
    EXPECT_LT(rounding, 20u);  // rounding only (levels on a boundary reach the next bin)
}

}  // namespace
