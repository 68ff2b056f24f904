// SPDX-License-Identifier: Apache-2.0
// Constant-fraction timing and Gaussian decomposition against closed forms
// (docs/time-resolved.md §12).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "mirage/core/rng.hpp"
#include "mirage/physics/linear_detector.hpp"
#include "mirage/physics/waveform.hpp"

namespace {

using namespace mirage::physics;
using mirage::sensor::PulseShape;

constexpr double kMmPerPs = 0.1498962;  // one-way range of a two-way delay

struct Counts {
    std::int64_t j0 = 0;
    std::vector<double> y;
};

// The digitised counts of `arrivals`, noise-free or with the pulse's normals from `rng`.
Counts digitised(const WaveformSynth& w, const LinearDetector& d,
                 const std::vector<Arrival>& arrivals, mirage::core::PulseRng* rng = nullptr) {
    std::int64_t lo = INT64_MAX, hi = INT64_MIN;
    for (const Arrival& a : arrivals) {
        lo = std::min(lo, w.first_sample(a.delay_ps) - 2);
        hi = std::max(hi, w.end_sample(a.delay_ps) + 2);
    }
    std::vector<double> n(static_cast<std::size_t>(hi - lo), 0.0), z(n.size());
    for (const Arrival& a : arrivals) w.add(a, lo, n);
    for (double& v : z) v = rng ? rng->normal() : 0.0;
    Counts c{lo, std::vector<double>(n.size())};
    d.digitise(n.data(), rng ? z.data() : nullptr, n.size(), c.y.data());
    return c;
}

std::vector<Echo> peaks(const LinearDetector& d, const Counts& c, bool noisy) {
    std::vector<Echo> e(8);
    e.resize(d.find_echoes(c.y.data(), c.y.size(), c.j0, 0.0, noisy, e.data(), e.size()));
    return e;
}

std::vector<Echo> decomposed(const LinearDetector& d, const Counts& c, double sigma_ns,
                             bool noisy) {
    std::vector<Echo> e = peaks(d, c, noisy);
    const std::size_t found = e.size();
    e.resize(8);
    e.resize(d.decompose(c.y.data(), c.y.size(), c.j0, 0.0, noisy, sigma_ns, e.data(), found, 8));
    return e;
}

// A Gaussian edge crosses f of the peak σ·√(−2 ln f) before it, whatever the amplitude and the
// clock phase; a fixed level instead walks with the amplitude.
TEST(ConstantFraction, the_edge_is_sigma_sqrt_minus_2_ln_f_before_the_peak_at_any_amplitude) {
    const PulseShape s = PulseShape::gaussian(4.0, "test");
    const WaveformSynth w(s, 1.0, "test");
    const LinearDetector d(LinearDetectorParams{}, "test");
    const double off = d.params().offset_counts;
    for (const double f : {0.2, 0.5, 0.8}) {
        const double lead_ps = 1e3 * s.sigma_ns() * std::sqrt(-2 * std::log(f));
        double worst_mm = 0, walk_lo = INFINITY, walk_hi = -INFINITY;
        for (const float pe : {60.0f, 200.0f, 900.0f, 3000.0f}) {
            for (std::int64_t delay = 500'000; delay < 501'000; delay += 61) {
                const Counts c = digitised(w, d, {{delay, pe, 0}});
                const auto e = peaks(d, c, false);
                ASSERT_EQ(e.size(), 1U);
                const double edge = d.leading_edge_ns(c.y.data(), c.y.size(), c.j0, off, e[0], f);
                ASSERT_FALSE(std::isnan(edge));
                const double err = (1e3 * edge + lead_ps - double(delay)) * kMmPerPs;
                worst_mm = std::max(worst_mm, std::abs(err));
                // A fixed level: 0.5 of the 60-pe echo's amplitude, on every echo.
                if (delay == 500'000) {
                    const double level = 0.5 * 60 * 4.0 / (s.sigma_ns() * std::sqrt(2 * M_PI));
                    const double fixed = d.leading_edge_ns(c.y.data(), c.y.size(), c.j0, off, e[0],
                                                           level / e[0].amplitude_counts);
                    walk_lo = std::min(walk_lo, fixed);
                    walk_hi = std::max(walk_hi, fixed);
                }
            }
        }
        EXPECT_LT(worst_mm, 0.1) << f;
        std::printf(
            "fraction %.1f: edge + sigma_p*sqrt(-2 ln f) within %.4f mm of the delay (60-3000 pe, "
            "17 clock phases); a fixed level walks %.1f mm over the same amplitudes\n",
            f, worst_mm, (walk_hi - walk_lo) * 1e3 * kMmPerPs);
        EXPECT_GT((walk_hi - walk_lo) * 1e3 * kMmPerPs, 100.0);
    }
}

// Two equal echoes closer than 2σ_p make one maximum; the decomposition recovers both, with
// their delays and photo-electrons, noise-free, from 1.6σ_p (its tolerance is 1 % of the peak).
TEST(Decomposition, recovers_two_echoes_that_make_one_maximum) {
    const PulseShape s = PulseShape::gaussian(4.0, "test");
    const WaveformSynth w(s, 1.0, "test");
    const LinearDetector d(LinearDetectorParams{}, "test");
    const double sigma_ps = 1e3 * s.sigma_ns();
    for (const double sep : {1.6, 1.8, 2.0, 2.5, 4.0}) {
        for (const float ratio : {1.0f, 3.0f}) {
            if (ratio > 1 && sep < 1.8) continue;  // one skewed peak: no unique decomposition
            double worst_mm = 0, worst_pe = 0;
            for (std::int64_t t1 = 300'000; t1 < 301'000; t1 += 125) {
                const auto t2 = t1 + static_cast<std::int64_t>(sep * sigma_ps);
                const Counts c = digitised(w, d, {{t1, 300.0f * ratio, 0}, {t2, 300.0f, 1}});
                if (sep < 2.0 && ratio == 1.0f) {
                    ASSERT_EQ(peaks(d, c, false).size(), 1U);
                }
                const auto e = decomposed(d, c, s.sigma_ns(), false);
                ASSERT_EQ(e.size(), 2U) << sep << " " << ratio << " " << t1;
                for (std::size_t k = 0; k < 2; ++k) {
                    const double want = double(k == 0 ? t1 : t2);
                    worst_mm = std::max(worst_mm, std::abs(1e3 * e[k].time_ns - want) * kMmPerPs);
                    const double pe = k == 0 ? 300.0 * ratio : 300.0;
                    worst_pe = std::max(worst_pe, std::abs(e[k].pe / pe - 1));
                }
            }
            EXPECT_LT(worst_mm, 1.0) << sep;
            EXPECT_LT(worst_pe, 0.01) << sep;
            std::printf(
                "two echoes %.1f sigma_p apart, %.0f:1: delays within %.4f mm, photo-electrons "
                "within %.4f %%\n",
                sep, double(ratio), worst_mm, 100 * worst_pe);
        }
    }
}

// With the digitiser's noise, a lone echo stays one component (no split from noise) and is
// timed better than by the three-point fit; two strong echoes 2.2σ_p apart, whose dip is far
// below 3σ of the noise, resolve, which the dip rule almost never does.
TEST(Decomposition, noise_splits_no_lone_echo_and_resolves_close_pairs_more_often) {
    const PulseShape s = PulseShape::gaussian(4.0, "test");
    const WaveformSynth w(s, 1.0, "test");
    const LinearDetector d(LinearDetectorParams{}, "test");
    constexpr int kPulses = 1000;
    int one = 0, pair_peaks = 0, pair_dec = 0;
    double rms_peak = 0, rms_dec = 0;
    for (int i = 0; i < kPulses; ++i) {
        mirage::core::PulseRng rng(11, static_cast<std::uint64_t>(i), 1);
        const std::int64_t t = 400'000 + 37 * i % 1000;
        const Counts c = digitised(w, d, {{t, 3000.0f, 0}}, &rng);
        const auto p = peaks(d, c, true);
        const auto e = decomposed(d, c, s.sigma_ns(), true);
        if (e.size() == 1) {
            ++one;
            rms_dec += std::pow((1e3 * e[0].time_ns - double(t)) * kMmPerPs, 2);
        }
        if (p.size() == 1) rms_peak += std::pow((1e3 * p[0].time_ns - double(t)) * kMmPerPs, 2);
        const auto t2 = t + static_cast<std::int64_t>(2.2e3 * s.sigma_ns());
        const Counts c2 = digitised(w, d, {{t, 3000.0f, 0}, {t2, 3000.0f, 1}}, &rng);
        pair_peaks += peaks(d, c2, true).size() == 2;
        pair_dec += decomposed(d, c2, s.sigma_ns(), true).size() == 2;
    }
    rms_dec = std::sqrt(rms_dec / one);
    rms_peak = std::sqrt(rms_peak / kPulses);
    std::printf(
        "lone 3000-pe echo: one component in %d of %d pulses, range RMS %.2f mm (peak fit %.2f "
        "mm); a pair 2.2 sigma_p apart resolved in %d (decomposition) and %d (dip rule) of %d\n",
        one, kPulses, rms_dec, rms_peak, pair_dec, pair_peaks, kPulses);
    EXPECT_GE(one, kPulses * 995 / 1000);
    EXPECT_LT(rms_dec, 1.2 * rms_peak);
    EXPECT_GT(pair_dec, pair_peaks);
    EXPECT_GE(pair_dec, kPulses * 9 / 10);
}

}  // namespace
