// SPDX-License-Identifier: Apache-2.0
// The expected waveform and the linear-mode detector against closed forms
// (docs/time-resolved.md §4, §7, §10).
#include "mirage/physics/waveform.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <span>
#include <vector>

#include "mirage/core/error.hpp"
#include "mirage/core/rng.hpp"
#include "mirage/physics/linear_detector.hpp"

namespace {

using namespace mirage::physics;
using mirage::sensor::PulseShape;

struct Wave {
    std::int64_t j0 = 0;
    std::vector<double> n;
};

Wave synth(const WaveformSynth& w, const std::vector<Arrival>& arrivals) {
    std::int64_t lo = INT64_MAX, hi = INT64_MIN;
    for (const Arrival& a : arrivals) {
        lo = std::min(lo, w.first_sample(a.delay_ps));
        hi = std::max(hi, w.end_sample(a.delay_ps));
    }
    Wave out{lo, std::vector<double>(static_cast<std::size_t>(hi - lo), 0.0)};
    for (const Arrival& a : arrivals) w.add(a, lo, out.n);
    return out;
}

std::vector<Echo> echoes(const LinearDetector& d, const Wave& w) {
    std::vector<double> counts(w.n.size());
    d.digitise(w.n.data(), nullptr, w.n.size(), counts.data());
    std::vector<Echo> e(8);
    e.resize(d.find_echoes(counts.data(), counts.size(), w.j0, 0.0, false, e.data(), e.size()));
    return e;
}

TEST(Waveform, one_arrival_has_its_energy_centroid_and_the_pulse_width) {
    const PulseShape s = PulseShape::gaussian(4.0, "test");
    const WaveformSynth w(s, 1.0, "test");
    for (std::int64_t delay : {100'000, 123'456, 667'001}) {
        const Wave v = synth(w, {{delay, 250.0f, 0}});
        double m0 = 0, m1 = 0, m2 = 0;
        for (std::size_t j = 0; j < v.n.size(); ++j) {
            const double t = static_cast<double>(v.j0 + static_cast<std::int64_t>(j));  // ns
            m0 += v.n[j];
            m1 += v.n[j] * t;
            m2 += v.n[j] * t * t;
        }
        const double mean = m1 / m0;
        EXPECT_NEAR(m0, 250.0, 250.0 * 1e-4);
        EXPECT_NEAR(mean * 1e3, static_cast<double>(delay), 1.0);  // ps
        EXPECT_NEAR(std::sqrt(m2 / m0 - mean * mean), s.sigma_ns(), s.sigma_ns() * 5e-3);
    }
}

// Discrete and waveform modes agree within 1 mm on a single facet: one arrival's echo, at any
// phase of the sample clock.
// A window that cuts an arrival's support short gets exactly the full synthesis's samples it holds
// and writes nothing past its end, for every length (the partial vector at the end of each) and
// for arrivals at several phases of the clock.
TEST(Waveform, a_window_cut_short_gets_the_same_samples_and_nothing_past_its_end) {
    const WaveformSynth w(PulseShape::gaussian(8.0, "test"), 1.0, "test");  // ~32 samples
    constexpr double kSentinel = -7.0;
    for (std::int64_t delay : {100'000, 100'031, 100'500, 100'969}) {
        const Arrival a{delay, 250.0f, 0};
        const Wave full = synth(w, {a});
        ASSERT_GT(full.n.size(), 24u);
        for (std::size_t len = 1; len <= full.n.size(); ++len) {
            std::vector<double> buf(len + 16, kSentinel);
            std::fill_n(buf.begin(), len, 0.0);
            w.add(a, full.j0, std::span<double>(buf.data(), len));
            for (std::size_t k = 0; k < len; ++k)
                ASSERT_EQ(buf[k], full.n[k])
                    << "delay " << delay << " length " << len << " at " << k;
            for (std::size_t k = len; k < buf.size(); ++k)
                ASSERT_EQ(buf[k], kSentinel)
                    << "delay " << delay << " length " << len << " at " << k;
        }
    }
}

// Any count, ties and far delays: the stable order by delay, whichever way it is computed.
TEST(Waveform, arrivals_sort_by_delay_stably) {
    mirage::core::PulseRng rng(5, 6, 7);
    std::vector<Arrival> tmp;
    for (int trial = 0; trial < 3000; ++trial) {
        const std::size_t n = std::size_t(trial % 41);
        std::vector<Arrival> v;
        for (std::size_t k = 0; k < n; ++k) {
            auto d = std::int64_t(rng.uniform() * (trial % 3 == 0 ? 8.0 : 1e6));  // ties
            if (trial % 7 == 0 && k == 0) d = -d - 1;                             // off the keys
            if (trial % 11 == 0 && k == 1) d = std::int64_t{1} << 60;
            v.push_back({d, 1.0f, std::uint32_t(k)});
        }
        std::vector<Arrival> want = v;
        std::stable_sort(want.begin(), want.end(),
                         [](auto& a, auto& b) { return a.delay_ps < b.delay_ps; });
        sort_by_delay(v, tmp);
        ASSERT_EQ(v.size(), want.size());
        for (std::size_t k = 0; k < n; ++k) {
            ASSERT_EQ(v[k].delay_ps, want[k].delay_ps) << "trial " << trial << " at " << k;
            ASSERT_EQ(v[k].hit, want[k].hit) << "trial " << trial << " at " << k;
        }
    }
}

// Moments of arrivals' delays about `about`: photo-electrons, mean, variance, third moment.
std::array<double, 4> moments(const std::vector<Arrival>& v, double about) {
    double m0 = 0, m1 = 0;
    for (const Arrival& a : v) m0 += a.pe, m1 += a.pe * (double(a.delay_ps) - about);
    const double mean = m1 / m0;
    double m2 = 0, m3 = 0;
    for (const Arrival& a : v) {
        const double d = double(a.delay_ps) - about - mean;
        m2 += a.pe * d * d;
        m3 += a.pe * d * d * d;
    }
    return {m0, about + mean, m2 / m0, m3 / m0};
}

// A cluster (delays within the window of its first) becomes two arrivals inside it that keep its
// photo-electrons, mean, variance and third moment, with its strongest arrival's hit; its
// waveform then differs from the cluster's by under 10⁻³ of the peak (docs/time-resolved.md §12).
TEST(Waveform, merged_arrivals_keep_four_moments_and_the_waveform) {
    const PulseShape shape = PulseShape::gaussian(4.0, "test");
    const WaveformSynth w(shape, 1.0, "test");
    const double window = 500.0 * shape.sigma_ns();  // ps: σ_p/2, as the renderer merges
    mirage::core::PulseRng rng(11, 2, 3);
    double worst = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const int n = 2 + trial % 18;
        std::vector<Arrival> v;
        for (int k = 0; k < n; ++k)
            v.push_back({500'000 + std::int64_t(rng.uniform() * (window - 1.0)),
                         float(1.0 + 99.0 * rng.uniform()), std::uint32_t(k)});
        std::sort(v.begin(), v.end(), [](auto& a, auto& b) { return a.delay_ps < b.delay_ps; });
        const Arrival strongest =
            *std::max_element(v.begin(), v.end(), [](auto& a, auto& b) { return a.pe < b.pe; });
        std::vector<Arrival> m = v;
        merge_arrivals(m, window);
        const auto a = moments(v, 500'000), b = moments(m, 500'000);
        const double sd = std::sqrt(a[2]);
        ASSERT_LE(m.size(), 2u);
        EXPECT_NEAR(b[0], a[0], a[0] * 1e-6);
        EXPECT_NEAR(b[1], a[1], 0.5);           // ps: nodes are whole ps
        EXPECT_NEAR(std::sqrt(b[2]), sd, 0.5);  // ps
        // ps³: a node at x moved by ≤ ½ ps moves the third moment by ≤ 1.5·((x − mean)² + σ²)
        double tol = 1.0;
        for (const Arrival& x : m) {
            const double d = double(x.delay_ps) - b[1];
            tol += 1.5 * double(x.pe) / b[0] * (d * d + a[2]);
        }
        EXPECT_NEAR(b[3], a[3], tol);
        for (const Arrival& x : m) {
            EXPECT_GE(x.delay_ps, v.front().delay_ps);
            EXPECT_LE(x.delay_ps, v.back().delay_ps);
            EXPECT_EQ(x.hit, strongest.hit);
        }
        const Wave full = synth(w, v);
        Wave merged{full.j0, std::vector<double>(full.n.size(), 0.0)};
        for (const Arrival& x : m) w.add(x, full.j0, merged.n);
        double peak = 0, diff = 0;
        for (std::size_t j = 0; j < full.n.size(); ++j) {
            peak = std::max(peak, full.n[j]);
            diff = std::max(diff, std::abs(full.n[j] - merged.n[j]));
        }
        worst = std::max(worst, diff / peak);
    }
    EXPECT_LT(worst, 1e-3);
    std::printf("largest waveform difference: %.2e of the peak\n", worst);
}

// Clusters far apart stay apart and in order; one alone, a cluster narrower than 1 ps and a
// window of zero leave one arrival each.
TEST(Waveform, merging_keeps_order_lone_arrivals_and_narrow_clusters) {
    std::vector<Arrival> v = {{1000, 5.0f, 0}, {1000, 7.0f, 1},   {1300, 1.0f, 2},  {1700, 2.0f, 3},
                              {9000, 4.0f, 4}, {20'000, 1.0f, 5}, {20'400, 3.0f, 6}};
    const std::vector<Arrival> original = v;
    std::vector<Arrival> same = v;
    merge_arrivals(same, 0.0);
    ASSERT_EQ(same.size(), original.size());
    for (std::size_t k = 0; k < v.size(); ++k) EXPECT_EQ(same[k].delay_ps, original[k].delay_ps);
    merge_arrivals(v, 850.0);
    // [1000, 1000, 1300, 1700] → two; 9000 alone; [20000, 20400] → two
    ASSERT_EQ(v.size(), 5u);
    for (std::size_t k = 1; k < v.size(); ++k) EXPECT_LE(v[k - 1].delay_ps, v[k].delay_ps);
    EXPECT_EQ(v[2].delay_ps, 9000);
    EXPECT_EQ(v[2].hit, 4u);
    EXPECT_EQ(v[0].hit, 1u);
    EXPECT_EQ(v[3].delay_ps, 20'000);
    EXPECT_EQ(v[4].delay_ps, 20'400);
    std::vector<Arrival> dark = {{700, 0.0f, 0}, {710, 0.0f, 1}};  // no light: no NaN
    merge_arrivals(dark, 850.0);
    ASSERT_EQ(dark.size(), 1u);
    EXPECT_EQ(dark[0].delay_ps, 700);
    EXPECT_EQ(dark[0].pe, 0.0f);
    std::vector<Arrival> narrow = {{5000, 1.0f, 0}, {5000, 2.0f, 1}, {5000, 3.0f, 2}};
    merge_arrivals(narrow, 850.0);
    ASSERT_EQ(narrow.size(), 1u);
    EXPECT_EQ(narrow[0].delay_ps, 5000);
    EXPECT_FLOAT_EQ(narrow[0].pe, 6.0f);
    EXPECT_EQ(narrow[0].hit, 2u);
}

TEST(LinearDetector, noise_free_echo_of_one_arrival_is_within_1_mm_at_any_clock_phase) {
    const PulseShape s = PulseShape::gaussian(4.0, "test");
    const WaveformSynth w(s, 1.0, "test");
    const LinearDetector d(LinearDetectorParams{}, "test");
    double worst_mm = 0;
    for (std::int64_t delay = 400'000; delay < 401'000; delay += 37) {
        const auto e = echoes(d, synth(w, {{delay, 500.0f, 0}}));
        ASSERT_EQ(e.size(), 1U) << delay;
        const double err_mm = (e[0].time_ns * 1e3 - static_cast<double>(delay)) * 0.1499;
        worst_mm = std::max(worst_mm, std::abs(err_mm));
        EXPECT_NEAR(e[0].sigma_ns, s.sigma_ns(), 0.01 * s.sigma_ns());
        EXPECT_NEAR(e[0].pe, 500.0, 5.0);
    }
    EXPECT_LT(worst_mm, 1.0);
    std::printf("worst range error of a noise-free single echo: %.4f mm\n", worst_mm);
}

// A digitiser whose period is not a whole number of ps (3 GS/s: 333.3 ps) times echoes as well:
// the sample clock is j·Δt in double.
TEST(LinearDetector, a_3_gsps_clock_times_one_echo_within_1_mm) {
    const PulseShape s = PulseShape::gaussian(4.0, "test");
    const WaveformSynth w(s, 1.0 / 3.0, "test");
    LinearDetectorParams p;
    p.sample_rate_gsps = 3.0;
    const LinearDetector d(p, "test");
    double worst_mm = 0;
    for (std::int64_t delay = 6'000'000; delay < 6'001'000; delay += 41) {
        const auto e = echoes(d, synth(w, {{delay, 500.0f, 0}}));
        ASSERT_EQ(e.size(), 1U) << delay;
        worst_mm = std::max(worst_mm, std::abs(e[0].time_ns * 1e3 - double(delay)) * 0.1499);
    }
    EXPECT_LT(worst_mm, 1.0);
    std::printf("3 GS/s, 900 m: worst range error of a noise-free echo %.4f mm\n", worst_mm);
}

// Two equal echoes show two maxima exactly when Δt > 2σ_p, i.e. ΔR > c·σ_p: the smallest
// separation that resolves is 2σ_p within one sample, at several clock phases.
TEST(LinearDetector, two_equal_echoes_resolve_when_their_distance_exceeds_c_sigma) {
    const PulseShape s = PulseShape::gaussian(4.0, "test");
    const WaveformSynth w(s, 1.0, "test");
    const LinearDetector d(LinearDetectorParams{}, "test");
    for (std::int64_t phase : {0, 250, 500, 750}) {
        const std::int64_t t1 = 300'000 + phase;
        std::int64_t first_split = -1;
        for (std::int64_t dt = 0; dt <= 8000; dt += 10) {
            const auto e = echoes(d, synth(w, {{t1, 300.0f, 0}, {t1 + dt, 300.0f, 1}}));
            if (e.size() == 2 && first_split < 0) first_split = dt;
            if (first_split >= 0) {
                EXPECT_EQ(e.size(), 2U) << "dt " << dt << " after a split";
            }
        }
        ASSERT_GE(first_split, 0);
        EXPECT_NEAR(static_cast<double>(first_split), 2e3 * s.sigma_ns(), 1000.0) << phase;
        std::printf(
            "clock phase %3lld ps: two echoes first resolve at %lld ps apart (2 sigma_p = "
            "%.0f ps, one sample = 1000 ps)\n",
            static_cast<long long>(phase), static_cast<long long>(first_split), 2e3 * s.sigma_ns());
    }
}

TEST(LinearDetector, excess_noise_follows_mcintyre) {
    auto f = [](double m, double k) {
        LinearDetectorParams p;
        p.apd_gain = m;
        p.apd_k = k;
        return LinearDetector(p, "test").excess_noise();
    };
    EXPECT_DOUBLE_EQ(f(1.0, 0.3), 1.0);
    EXPECT_DOUBLE_EQ(f(50.0, 1.0), 50.0);
    EXPECT_DOUBLE_EQ(f(50.0, 0.0), 2.0 - 1.0 / 50.0);
    EXPECT_NEAR(f(100.0, 0.02), 0.02 * 100 + 0.98 * (2 - 0.01), 1e-12);
}

// Sample noise: variance g²(F·n + σ_th²) (+ 1/12 count² of rounding) within 2 % over 2e5 draws.
TEST(LinearDetector, sample_noise_has_the_shot_excess_and_thermal_variance) {
    LinearDetectorParams p;
    p.bits = 16;
    p.offset_counts = 1000;
    const LinearDetector d(p, "test");
    constexpr std::size_t kN = 200'000;
    std::vector<double> n(kN, 100.0), z(kN), c(kN);
    mirage::core::PulseRng rng(7, 1, 1);
    for (double& v : z) v = rng.normal();
    d.digitise(n.data(), z.data(), kN, c.data());
    double m = 0, v = 0;
    for (double x : c) m += x;
    m /= kN;
    for (double x : c) v += (x - m) * (x - m);
    v /= kN - 1;
    const double g = p.gain_counts_per_pe;
    const double want = g * g * (d.excess_noise() * 100.0 + 4.0) + 1.0 / 12;
    EXPECT_NEAR(v, want, 0.02 * want);
    std::printf("sample variance %.1f counts^2 against g^2(F n + th^2) + 1/12 = %.1f (%+.2f %%)\n",
                v, want, 100 * (v / want - 1));
    EXPECT_NEAR(m, 1000.0 + g * 100.0, 4 * std::sqrt(want / kN));  // 4 standard errors
}

TEST(LinearDetector, impossible_settings_are_config_errors_naming_the_key) {
    auto fails = [](auto set, const char* key) {
        LinearDetectorParams p;
        set(p);
        try {
            LinearDetector d(p, "s.yaml");
            ADD_FAILURE() << key << " accepted";
        } catch (const mirage::ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
        }
    };
    fails([](auto& p) { p.bits = 0; }, "detector.bits");
    fails([](auto& p) { p.bits = 33; }, "detector.bits");
    fails([](auto& p) { p.apd_k = 1.5; }, "detector.apd_k");
    fails([](auto& p) { p.gain_counts_per_pe = 0; }, "detector.gain_counts_per_pe");
    fails([](auto& p) { p.threshold_counts = 5000; }, "detector.threshold_counts");
    fails([](auto& p) { p.sample_rate_gsps = 0; }, "detector.sample_rate_gsps");
    EXPECT_THROW(WaveformSynth(PulseShape::gaussian(4.0, "t"), 0.0, "s.yaml"), mirage::ConfigError);
}

}  // namespace
