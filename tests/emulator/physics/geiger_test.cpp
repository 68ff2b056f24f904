// SPDX-License-Identifier: Apache-2.0
// Geiger-mode detection against closed forms (docs/photon-counting.md §2): the first event's
// histogram, a leaf over the ground, noise blocking a gate, Coates' correction and the counting
// rates of a dead-time-limited detector, each from counter-based draws over 1e6 gates or more.
#include "mirage/physics/geiger.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "mirage/core/error.hpp"

namespace {

using mirage::core::PulseRng;
using mirage::physics::coates;
using mirage::physics::DeadTime;
using mirage::physics::EventKind;
using mirage::physics::EventRate;
using mirage::physics::first_event_bin;
using mirage::physics::geiger_events;
using mirage::physics::GeigerEvent;
using mirage::physics::GeigerPixel;

// A framed pixel: a dead time longer than any gate, so the first event only.
const GeigerPixel kFirstOnly{{1e9, false}};

constexpr std::uint64_t kSeed = 20261127;
constexpr std::uint32_t kStream = 9;

// 200 bins of 1 ns: 2 MHz of noise (0.002 a bin) and a return of `pe` primary events in a
// Gaussian of σ = 2 bins about bin 100.
EventRate noisy_return(double pe) {
    std::vector<double> n(200, 0.0);
    for (int k = 0; k < 200; ++k) {
        const double x = (k - 100) / 2.0;
        n[std::size_t(k)] = pe * std::exp(-0.5 * x * x) / (2.0 * std::sqrt(2 * M_PI));
    }
    return EventRate(n, 0.002, 1.0);
}

// First events (a dead time longer than the gate) over `gates` gates, as a histogram of bins;
// the last entry counts gates without one.
std::vector<std::uint64_t> first_events(const EventRate& rate, std::uint64_t gates) {
    std::vector<std::uint64_t> h(rate.bins() + 1, 0);
    std::vector<GeigerEvent> t;
    for (std::uint64_t g = 0; g < gates; ++g) {
        PulseRng rng(kSeed, g, kStream);
        geiger_events(rate, kFirstOnly, rng, 1, t);
        h[t.empty() ? rate.bins()
                    : std::min(rate.bins() - 1, std::size_t(t[0].t_ns / rate.bin_ns()))]++;
    }
    return h;
}

// P(first event in bin k) = e^(−Λ_k)·(1 − e^(−n_k)) for every bin within 0.5 % absolute over
// 1e6 gates, and the draw by inverse transform agrees with the event loop's.
TEST(Geiger, first_event_histogram_follows_the_closed_form) {
    const EventRate rate = noisy_return(1.5);
    const std::uint64_t gates = 1'000'000;
    const auto h = first_events(rate, gates);
    double worst = 0, none = double(h.back()) / double(gates);
    for (std::size_t k = 0; k < rate.bins(); ++k)
        worst = std::max(worst,
                         std::abs(double(h[k]) / double(gates) - rate.first_event_probability(k)));
    std::printf(
        "first event over 1e6 gates: worst bin %.5f absolute; no event %.4f against "
        "%.4f\n",
        worst, none, std::exp(-rate.total()));
    EXPECT_LT(worst, 0.005);
    EXPECT_NEAR(none, std::exp(-rate.total()), 0.005);
    for (std::uint64_t g = 0; g < 1000; ++g) {
        PulseRng a(kSeed, g, kStream), b(kSeed, g, kStream);
        std::vector<GeigerEvent> t;
        geiger_events(rate, kFirstOnly, a, 1, t);
        const std::size_t k = first_event_bin(rate, b.uniform());
        ASSERT_EQ(t.empty() ? rate.bins() : std::size_t(t[0].t_ns), k) << "gate " << g;
    }
}

// A leaf (N1 = 0.5 primary events) in front of the ground (N2 = 2), no noise: P_leaf = 1 − e^(−N1)
// = 0.3935, P_ground = e^(−N1)(1 − e^(−N2)) = 0.5244, P_none = e^(−N1−N2) = 0.0821, within 0.5 %
// absolute over 1e6 pulses, although the leaf's return is the weaker; ln 0.05 / ln(1 − P_ground)
// = 4.03 pulses see the ground at 95 %: five see it at 1 − 0.4756⁵ = 0.9755.
TEST(Geiger, a_leaf_over_the_ground_fires_by_the_poisson_law) {
    std::vector<double> n(100, 0.0);
    n[30] = 0.5;
    n[70] = 2.0;
    const EventRate rate(n, 0.0, 1.0);
    const std::uint64_t gates = 1'000'000;
    const auto h = first_events(rate, gates);
    const double leaf = double(h[30]) / double(gates), ground = double(h[70]) / double(gates),
                 none = double(h[100]) / double(gates);
    const double p_ground = std::exp(-0.5) * (1 - std::exp(-2.0));
    std::printf(
        "leaf over ground, 1e6 pulses: leaf %.4f (0.3935), ground %.4f (0.5244), none "
        "%.4f (0.0821); 95 %% needs %.2f pulses\n",
        leaf, ground, none, std::log(0.05) / std::log(1 - p_ground));
    EXPECT_NEAR(leaf, 1 - std::exp(-0.5), 0.005);
    EXPECT_NEAR(ground, p_ground, 0.005);
    EXPECT_NEAR(none, std::exp(-2.5), 0.005);
    EXPECT_NEAR(std::log(0.05) / std::log(1 - p_ground), 4.03, 0.01);
    std::uint64_t seen = 0, groups = 0;
    for (std::uint64_t g = 0; g + 5 <= gates; g += 5, ++groups) {
        std::vector<GeigerEvent> t;
        bool any = false;
        for (std::uint64_t p = g; p < g + 5; ++p) {
            PulseRng rng(kSeed, p, kStream);
            geiger_events(rate, kFirstOnly, rng, 1, t);
            any |= !t.empty() && std::size_t(t[0].t_ns) == 70;
        }
        seen += any;
    }
    EXPECT_NEAR(double(seen) / double(groups), 1 - std::pow(1 - p_ground, 5), 0.005);
}

// 1 MHz of noise in a 2 µs gate: no event with probability e^(−2) = 0.1353 (within 0.5 %
// absolute over 1e6 gates); a return after it is blocked by that much.
TEST(Geiger, noise_blocks_the_gate) {
    const EventRate rate(std::vector<double>(2000, 0.0), 0.001, 1.0);
    const auto h = first_events(rate, 1'000'000);
    const double none = double(h.back()) / 1e6;
    std::printf("1 MHz over a 2 us gate: no event %.4f against e^-2 = %.4f\n", none,
                std::exp(-2.0));
    EXPECT_NEAR(none, std::exp(-2.0), 0.005);
}

// Coates' correction undoes the blocking: over 1e6 gates the mean of n̂ over the 90 noise bins
// before the return and the sum of n̂ over the return (bins 90–109, noise taken off) recover
// 0.002 and 1.5 within 1 %, where the raw share of first events in those bins falls short by
// the gates already fired.
TEST(Geiger, coates_correction_recovers_the_rate) {
    const EventRate rate = noisy_return(1.5);
    const std::uint64_t gates = 1'000'000;
    auto h = first_events(rate, gates);
    h.pop_back();
    const auto est = coates(h, gates);
    double noise = 0, signal = 0, raw = 0;
    for (std::size_t k = 0; k < 90; ++k) noise += est[k] / 90;
    for (std::size_t k = 90; k < 110; ++k) {
        signal += est[k] - 0.002;
        raw += double(h[k]) / double(gates) - 0.002;
    }
    std::printf(
        "Coates over 1e6 gates: noise %.6f per bin (0.002), return %.4f (1.5; raw first "
        "events %.4f)\n",
        noise, signal, raw);
    EXPECT_NEAR(noise / 0.002, 1.0, 0.01);
    EXPECT_NEAR(signal / 1.5, 1.0, 0.01);
    EXPECT_LT(raw, 0.9 * 1.5);
}

// A free-running pixel under 10 MHz with a 50 ns dead time, over 10 ms: the counting rate
// r/(1 + rτ) = 6.667 MHz (non-paralyzable) and r·e^(−rτ) = 6.065 MHz (paralyzable) within 1 %.
TEST(Geiger, dead_time_limits_the_counting_rate) {
    const double r = 0.01;  // per ns
    const EventRate rate(std::vector<double>(100'000, 0.0), r * 100.0, 100.0);
    for (const bool paralyzable : {false, true}) {
        const DeadTime dead{50.0, paralyzable};
        PulseRng rng(kSeed, paralyzable ? 1 : 0, kStream);
        std::vector<GeigerEvent> t;
        geiger_events(rate, {dead}, rng, 1'000'000, t);
        const double got = double(t.size()) / rate.gate_ns();
        const double want = mirage::physics::observed_rate(r, dead);
        std::printf("%s dead time 50 ns at 10 MHz: %.4f MHz counted, %.4f MHz by the law\n",
                    paralyzable ? "paralyzable" : "non-paralyzable", got * 1e3, want * 1e3);
        EXPECT_NEAR(got / want, 1.0, 0.01);
        for (std::size_t k = 1; k < t.size(); ++k)
            ASSERT_GE(t[k].t_ns - t[k - 1].t_ns, 50.0 - 1e-9);
    }
}

// Paralyzable under 60 MHz with a 50 ns dead time (rτ = 3: most dead spans are restarted
// several times), over 100 ms: r·e^(−rτ) = 2.987 MHz within 1 %.
TEST(Geiger, a_paralyzable_pixel_restarted_many_times_counts_by_the_law) {
    const double r = 0.06;  // per ns
    const EventRate rate(std::vector<double>(1'000'000, 0.0), r * 100.0, 100.0);
    const DeadTime dead{50.0, true};
    PulseRng rng(kSeed, 2, kStream);
    std::vector<GeigerEvent> t;
    geiger_events(rate, {dead}, rng, 10'000'000, t);
    const double got = double(t.size()) / rate.gate_ns();
    const double want = mirage::physics::observed_rate(r, dead);
    std::printf("paralyzable dead time 50 ns at 60 MHz: %.4f MHz counted, %.4f MHz by the law\n",
                got * 1e3, want * 1e3);
    EXPECT_NEAR(got / want, 1.0, 0.01);
}

// Against an independent draw of every primary event (std::mt19937_64, each one restarting the
// dead time while the pixel is dead): a paralyzable pixel under 50 MHz of noise with a return of
// 400 photo-electrons at 300 ns (σ 2 ns), τ = 20 ns, 20 000 gates of 1 µs each way. The
// detections per gate agree within 1 %, and their counts in 20 ns bins from 260 to 460 ns (the
// return and the re-arming after it) within 5 standard errors.
TEST(Geiger, a_paralyzed_span_drawn_a_dead_time_at_a_time_matches_every_event_drawn) {
    std::vector<double> n(4000, 0.05 * 0.25);
    for (int k = 0; k < 4000; ++k) {
        const double x = (k * 0.25 - 300.0) / 2.0;
        n[std::size_t(k)] += 400.0 * 0.25 * std::exp(-0.5 * x * x) / (2.0 * std::sqrt(2 * M_PI));
    }
    const EventRate rate(n, 0.0, 0.25);
    const double tau = 20.0;
    const int gates = 20'000, bins = 10;
    std::vector<double> ours(bins, 0.0), every(bins, 0.0);
    double ours_n = 0, every_n = 0;
    const auto tally = [&](double t_ns, std::vector<double>& h, double& count) {
        count += 1;
        const int b = int(std::floor((t_ns - 260.0) / 20.0));
        if (b >= 0 && b < bins) h[std::size_t(b)] += 1;
    };
    std::vector<GeigerEvent> t;
    std::mt19937_64 gen(20261129);
    std::exponential_distribution<double> exp1(1.0);
    for (int g = 0; g < gates; ++g) {
        PulseRng rng(kSeed, std::uint64_t(g), kStream);
        geiger_events(rate, {{tau, true}}, rng, 1000, t);
        for (const auto& e : t) tally(e.t_ns, ours, ours_n);
        double armed = 0;
        for (double level = exp1(gen); level < rate.total(); level += exp1(gen)) {
            const double at = rate.time_at(level);
            if (at >= armed) tally(at, every, every_n);
            armed = std::max(armed, at + tau);
        }
    }
    std::printf("detections per gate: %.4f drawn a dead time at a time, %.4f every event\n",
                ours_n / gates, every_n / gates);
    EXPECT_NEAR(ours_n / every_n, 1.0, 0.01);
    for (int b = 0; b < bins; ++b) {
        const std::size_t i = std::size_t(b);
        std::printf("  %3d-%3d ns: %7.0f %7.0f\n", 260 + 20 * b, 280 + 20 * b, ours[i], every[i]);
        EXPECT_LE(std::fabs(ours[i] - every[i]), 5.0 * std::sqrt(ours[i] + every[i]) + 1.0) << b;
    }
}

// Truth flags, jitter and afterpulses. A first event in bin k is signal with probability
// S_k/n_k: over 1e6 gates the share flagged signal matches Σ_k P(first in k)·S_k/n_k within
// 0.5 % absolute. A return of N = 20 events in one 1 ns bin fires at Λ = E, E ~ Exp(1): E/N ns
// into the bin, variance 1/N²; with 0.3 ns of jitter the reported times' variance is
// 1/N² + 0.09 ns² (within 3 %). An afterpulse probability of 0.1 with a 100 ns mean delay,
// 20 ns of dead time, that one certain detection, no noise and a 10 µs gate: the second event
// is an afterpulse in 0.1·e^(−20/100) = 0.0819 of the gates (within 5 %).
TEST(Geiger, truth_flags_jitter_and_afterpulses_follow_their_parameters) {
    const EventRate rate = noisy_return(1.5);
    const std::uint64_t gates = 1'000'000;
    double want = 0;
    for (std::size_t k = 0; k < rate.bins(); ++k)
        want += rate.first_event_probability(k) * rate.signal_share(k);
    std::vector<GeigerEvent> t;
    std::uint64_t signal = 0;
    for (std::uint64_t g = 0; g < gates; ++g) {
        PulseRng rng(kSeed, g, kStream);
        geiger_events(rate, kFirstOnly, rng, 1, t);
        signal += !t.empty() && t[0].kind == EventKind::Signal;
    }
    const double got = double(signal) / double(gates);
    std::vector<double> one(10'000, 0.0);
    one[40] = 20.0;
    const EventRate sharp(one, 0.0, 1.0);
    GeigerPixel jittery = kFirstOnly;
    jittery.jitter_ns = 0.3;
    double m = 0, m2 = 0;
    GeigerPixel trapping{{20.0, false}, 0.0, 0.1, 100.0};
    std::uint64_t after = 0;
    const std::uint64_t n = 200'000;
    for (std::uint64_t g = 0; g < n; ++g) {
        PulseRng rng(kSeed, g, kStream);
        geiger_events(sharp, jittery, rng, 1, t);
        m += t[0].t_ns;
        m2 += t[0].t_ns * t[0].t_ns;
        PulseRng rng2(kSeed, g, kStream + 1);
        geiger_events(sharp, trapping, rng2, 4, t);
        after += t.size() >= 2 && t[1].kind == EventKind::Afterpulse;
    }
    const double var = m2 / double(n) - (m / double(n)) * (m / double(n));
    const double var_want = 1.0 / 400.0 + 0.09, ap_want = 0.1 * std::exp(-0.2);
    const double ap = double(after) / double(n);
    std::printf(
        "signal-flagged first events %.4f (%.4f); jittered time variance %.4f ns2 "
        "(%.4f); afterpulses %.4f of gates (%.4f)\n",
        got, want, var, var_want, ap, ap_want);
    EXPECT_NEAR(got, want, 0.005);
    EXPECT_NEAR(var / var_want, 1.0, 0.03);
    EXPECT_NEAR(ap / ap_want, 1.0, 0.05);
}

TEST(Geiger, bad_gates_are_configuration_errors) {
    EXPECT_THROW(EventRate(std::vector<double>{1.0}, 0.0, 0.0), mirage::ConfigError);
    EXPECT_THROW(EventRate(std::vector<double>{-1.0}, 0.0, 1.0), mirage::ConfigError);
    EXPECT_THROW(EventRate(std::vector<double>{NAN}, 0.0, 1.0), mirage::ConfigError);
    EXPECT_THROW(EventRate(std::vector<double>{1.0}, -1.0, 1.0), mirage::ConfigError);
    const EventRate empty(std::vector<double>{}, 0.0, 1.0);
    PulseRng rng(kSeed, 0, kStream);
    std::vector<GeigerEvent> t{{1.0, EventKind::Signal}};
    geiger_events(empty, {}, rng, 10, t);
    EXPECT_TRUE(t.empty());
    EXPECT_TRUE(std::isnan(coates(std::vector<std::uint64_t>{5, 0}, 5)[1]));
}

}  // namespace

namespace {

// The pipeline's in-place build (begin/add/finish) gives the rate the checked constructor gives
// for the same bins: a repeated bin sums, and what the constructor would refuse (a bin past the
// gate, out of order, negative or not finite) adds nothing instead of throwing.
TEST(Geiger, a_rate_built_in_place_equals_the_checked_one) {
    const std::vector<mirage::physics::SignalBin> bins{{3, 0.25}, {4, 1.5}, {9, 0.125}};
    const EventRate want(40, bins, 0.01, 0.5);
    EventRate got;
    got.begin(40, 0.01, 0.5);
    got.add(3, 0.125);
    got.add(3, 0.125);  // the same bin again: summed
    got.add(4, 1.5);
    got.add(2, 7.0);   // out of order
    got.add(5, -1.0);  // negative
    got.add(6, NAN);
    got.add(7, INFINITY);
    got.add(9, 0.125);
    got.add(40, 3.0);  // past the gate
    got.finish();
    EXPECT_EQ(got.last_key(), 9);
    EXPECT_DOUBLE_EQ(got.total(), want.total());
    for (std::size_t k = 0; k <= 40; ++k) {
        EXPECT_DOUBLE_EQ(got.before(k), want.before(k)) << k;
        if (k < 40) {
            EXPECT_DOUBLE_EQ(got.in(k), want.in(k)) << k;
        }
    }
    for (const double level : {0.0, 0.02, 0.3, 1.0, 1.9, 2.1, 2.2})
        EXPECT_DOUBLE_EQ(got.time_at(level), want.time_at(level)) << level;
    got.begin(40, 0.0, 0.5);  // reused: nothing of the last build stays
    got.finish();
    EXPECT_EQ(got.last_key(), -1);
    EXPECT_EQ(got.total(), 0.0);
}

// A run of bins (a pulse's shares times its photo-electrons) equals the same bins added one by
// one: cut at the gate's opening and close, zero shares left out, and merged where it starts at
// or before the last bin given.
TEST(Geiger, a_run_of_bins_equals_its_bins_one_by_one) {
    const std::vector<double> w{0.0, 0.125, 0.5, 0.25, 0.0, 0.125};
    for (const std::int64_t k0 : {-3, 0, 2, 7, 10, 13}) {
        for (const bool after_one : {false, true}) {
            EventRate run, one;
            run.begin(12, 0.01, 0.5);
            one.begin(12, 0.01, 0.5);
            if (after_one) {
                run.add(4, 0.75);
                one.add(4, 0.75);
            }
            run.add_run(k0, 2.0, w.data(), w.size());
            for (std::size_t j = 0; j < w.size(); ++j) {
                const std::int64_t k = k0 + std::int64_t(j);
                if (k >= 0 && k < 12) one.add(std::uint32_t(k), 2.0 * w[j]);
            }
            run.finish();
            one.finish();
            EXPECT_EQ(run.last_key(), one.last_key()) << k0;
            EXPECT_DOUBLE_EQ(run.total(), one.total()) << k0;
            for (std::size_t k = 0; k <= 12; ++k)
                EXPECT_DOUBLE_EQ(run.before(k), one.before(k)) << k0 << " " << k;
        }
    }
}

// A first level drawn ahead of the rate gives the events of the draw that makes its own.
TEST(Geiger, events_from_a_drawn_first_level_equal_the_plain_draw) {
    const EventRate rate = noisy_return(2.0);
    const GeigerPixel pixel{{5.0, false}, 0.3, 0.1, 20.0};
    std::vector<GeigerEvent> a, b;
    for (std::uint64_t g = 0; g < 2000; ++g) {
        PulseRng r1(kSeed, g, kStream), r2(kSeed, g, kStream);
        geiger_events(rate, pixel, r1, 8, a);
        const double level = mirage::physics::first_level(r2);
        geiger_events(rate, pixel, r2, level, 8, b);
        ASSERT_EQ(a.size(), b.size()) << g;
        for (std::size_t j = 0; j < a.size(); ++j) {
            EXPECT_EQ(a[j].t_ns, b[j].t_ns);
            EXPECT_EQ(a[j].kind, b[j].kind);
        }
    }
}

}  // namespace

namespace free_running {

using mirage::physics::GeigerWindow;

// Windows of a free-running pixel chained one period apart, each armed from where the one before
// left it (docs/photon-counting.md §2.1): under a constant rate r the count rate is the
// dead-time law's, r/(1 + rτ) or r·e^(−rτ), within 1 %, even with a dead time longer than the
// period (10 MHz, τ = 50 ns, windows of 40 ns, 250 000 of them). Re-armed at every window
// instead, the count is far above the law.
TEST(Geiger, a_free_running_pixel_carries_its_dead_time_across_windows) {
    const double r = 0.01, period = 40.0;  // per ns; ns
    const EventRate rate(std::vector<double>(160, 0.0), r * 0.25, 0.25);
    const std::uint64_t windows = 250'000;
    for (const bool paralyzable : {false, true}) {
        const GeigerPixel pixel{{50.0, paralyzable}};
        std::uint64_t carried = 0, rearmed = 0;
        double armed_from = 0;
        std::vector<GeigerEvent> t;
        for (std::uint64_t w = 0; w < windows; ++w) {
            PulseRng rng(kSeed, w, kStream);
            const double level = mirage::physics::first_level(rng);
            const double end =
                geiger_events(rate, pixel, rng, level, GeigerWindow{armed_from, period, 15}, t);
            for (const auto& e : t) ASSERT_GE(e.t_ns, armed_from);
            carried += t.size();
            armed_from = end - period;
            PulseRng again(kSeed, w, kStream);
            geiger_events(rate, pixel, again, 15, t);
            rearmed += t.size();
        }
        const double span = double(windows) * period;
        const double want = mirage::physics::observed_rate(r, pixel.dead);
        const double got = double(carried) / span;
        std::printf(
            "%s, tau 50 ns over 40 ns windows at 10 MHz: carried %.4f MHz, law %.4f MHz, "
            "re-armed every window %.4f MHz\n",
            paralyzable ? "paralyzable" : "non-paralyzable", got * 1e3, want * 1e3,
            double(rearmed) / span * 1e3);
        EXPECT_NEAR(got / want, 1.0, 0.01);
        EXPECT_GT(double(rearmed) / span / want, 1.2);
    }
}

// Tracking past the report: the window reports its detections before report_ns only (at most
// max_events), draws the same ones as a gated pixel that reports them all, and returns the last
// one's re-arming time.
TEST(Geiger, a_free_running_window_reports_before_its_close_and_tracks_to_its_end) {
    const EventRate rate(std::vector<double>(4000, 0.0), 0.02, 0.25);  // 80 MHz over 1 µs
    const GeigerPixel pixel{{30.0, false}};
    for (std::uint64_t g = 0; g < 200; ++g) {
        std::vector<GeigerEvent> all, part;
        PulseRng a(kSeed, g, kStream), b(kSeed, g, kStream);
        geiger_events(rate, pixel, a, 1000, all);
        const double level = mirage::physics::first_level(b);
        const double end = geiger_events(rate, pixel, b, level, GeigerWindow{0, 500, 3}, part);
        ASSERT_GT(all.size(), 3u);
        std::size_t before = 0;
        while (before < all.size() && all[before].t_ns < 500) ++before;
        ASSERT_EQ(part.size(), std::min<std::size_t>(before, 3));
        for (std::size_t k = 0; k < part.size(); ++k) ASSERT_EQ(part[k].t_ns, all[k].t_ns);
        ASSERT_DOUBLE_EQ(end, all.back().t_ns + 30.0);
    }
}

// A window opening dead past its end takes nothing; paralyzable, its primary events keep the
// pixel dead beyond where it was (re-arming later than it opened dead).
TEST(Geiger, a_window_that_opens_dead_past_its_end_only_extends_a_paralyzable_dead_time) {
    const EventRate rate(std::vector<double>(400, 0.0), 0.5, 0.25);  // 2 per ns
    std::vector<GeigerEvent> t;
    PulseRng rng(kSeed, 1, kStream);
    const double level = mirage::physics::first_level(rng);
    EXPECT_EQ(geiger_events(rate, {{200.0, false}}, rng, level, GeigerWindow{150, 100, 4}, t),
              150.0);
    EXPECT_TRUE(t.empty());
    PulseRng again(kSeed, 1, kStream);
    const double end =
        geiger_events(rate, {{200.0, true}}, again, mirage::physics::first_level(again),
                      GeigerWindow{150, 100, 4}, t);
    EXPECT_TRUE(t.empty());
    EXPECT_GT(end, 299.0);  // its last primary event lies within 1 ns of the window's end
}

// A paralyzable pixel under a noise floor it cannot outlast (50 per ns against a dead time of
// 50 ns: a gap that long has probability e^(−2500)) fires once, at its first primary event, and
// re-arms a dead time after the gate's last primary event, which lies Exp(rate) before the gate's
// end: over 100 000 windows of 2 µs the mean of that gap is 1/rate within 2 %. A dead span is
// drawn a dead time at a time (docs/photon-counting.md §2); drawn a primary event at a time, 20
// windows of 80 µs (4·10⁶ primary events each) took seconds, and now take well under 0.5 s.
TEST(Geiger, a_paralyzable_pixel_under_a_floor_it_cannot_outlast_fires_once) {
    const double r = 50.0;  // per ns
    const GeigerPixel pixel{{50.0, true}};
    std::vector<GeigerEvent> t;
    const auto window = [&](const EventRate& rate, std::uint64_t w) {
        PulseRng rng(kSeed, w, kStream);
        const double level = mirage::physics::first_level(rng);
        const double end =
            geiger_events(rate, pixel, rng, level, GeigerWindow{0, rate.gate_ns(), 3}, t);
        EXPECT_EQ(t.size(), 1u);
        EXPECT_NEAR(t.at(0).t_ns, level / r, 1e-9);
        EXPECT_LE(end - 50.0, rate.gate_ns());
        PulseRng gated(kSeed, w, kStream);
        geiger_events(rate, pixel, gated, 3, t);
        EXPECT_EQ(t.size(), 1u);
        return rate.gate_ns() - (end - 50.0);
    };
    const EventRate long_gate(std::vector<double>(320'000, 0.0), r * 0.25, 0.25);
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t w = 0; w < 20; ++w) window(long_gate, w);
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
    EXPECT_LT(took.count(), 0.5);
    const EventRate rate(std::vector<double>(8'000, 0.0), r * 0.25, 0.25);
    double gap_sum = 0;
    const int windows = 100'000;
    for (int w = 0; w < windows; ++w) gap_sum += window(rate, std::uint64_t(w));
    const double mean_gap = gap_sum / windows;
    std::printf(
        "20 windows of 80 us: %.3f s; last primary event before a 2 us gate's end: mean "
        "%.5f ns, 1/rate %.5f ns\n",
        took.count(), mean_gap, 1.0 / r);
    EXPECT_NEAR(mean_gap * r, 1.0, 0.02);
}
}  // namespace free_running
