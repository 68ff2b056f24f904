// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

#include "mirage/core/rng.hpp"
#include "mirage/physics/radiometry.hpp"

namespace mp = mirage::physics;

namespace {

mp::Radiometry noisy_radiometry() {
    mirage::sensor::BeamParams b;
    b.wavelength_m = 905e-9;
    mirage::sensor::ReceiverParams rx;
    rx.detector_area_m2 = 1e-7;
    rx.quantum_efficiency = 0.7;
    rx.detector_bandwidth_m = 20e-9;
    rx.integration_time_s = 1e-6;
    rx.noise_irradiance_sigma = 0.01;  // W/(m²·µm) → a ≈ 64 e- per unit z
    rx.threshold_gamma = 3.0;
    return mp::Radiometry(b, rx, {});
}

// t with P(|z| > t) = erfc(t/√2) = p, by bisection (erfc is decreasing).
double two_sided_quantile(double p) {
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// N_laser that puts the void probability at p: solve (N/γ)² − N − N_o = a²t² for N > 0.
double laser_for_void_probability(double p, double a, double n_other, double gamma) {
    const double t = two_sided_quantile(p);
    const double c = n_other + a * a * t * t;
    return 0.5 * gamma * gamma * (1.0 + std::sqrt(1.0 + 4.0 * c / (gamma * gamma)));
}

}  // namespace

TEST(VoidProbability, closed_form_edge_cases) {
    const mp::Radiometry r = noisy_radiometry();
    EXPECT_EQ(r.void_probability(0.0, 5.0), 1.0);  // nothing returned
    EXPECT_EQ(r.void_probability(-1.0, 0.0), 1.0);
    EXPECT_EQ(r.void_probability(5.0, 0.0), 1.0);     // (5/3)² < 5: shot noise alone wins
    EXPECT_LT(r.void_probability(1e6, 0.0), 1e-300);  // far above the floor
    // Without detector noise the rule is deterministic.
    mirage::sensor::ReceiverParams rx;
    rx.threshold_gamma = 3.0;
    const mp::Radiometry quiet({}, rx, {});
    EXPECT_EQ(quiet.noise_floor_electrons(), 0.0);
    EXPECT_EQ(quiet.void_probability(100.0, 100.0), 0.0);  // (100/3)² = 1111 > 200
    EXPECT_FALSE(quiet.is_void(100.0, 100.0, 5.0));
    EXPECT_EQ(quiet.void_probability(20.0, 100.0), 1.0);
    EXPECT_TRUE(quiet.is_void(20.0, 100.0, 0.0));
}

TEST(VoidProbability, matches_monte_carlo_with_pulse_rng_at_three_levels) {
    // 1e6 draws of z from mirage::core::PulseRng (one generator per pulse, as the pipeline
    // does), counting is_void. Bound: 5 binomial standard deviations, 5·sqrt(p(1−p)/n)
    // ≤ 2.5e-3 absolute — tighter than 1 % absolute, and a correct implementation fails it with
    // probability < 1e-6 (the draws are seeded, so the outcome is in any case reproducible).
    const mp::Radiometry r = noisy_radiometry();
    const double a = r.noise_floor_electrons();
    ASSERT_GT(a, 1.0);
    const double n_other = 250.0;
    constexpr std::uint64_t kDraws = 1'000'000;
    std::uint32_t stream = 0;
    for (double target : {0.1, 0.5, 0.9}) {
        const double n_laser = laser_for_void_probability(target, a, n_other, 3.0);
        const double predicted = r.void_probability(n_laser, n_other);
        EXPECT_NEAR(predicted, target, 1e-9);
        std::uint64_t voids = 0;
        for (std::uint64_t k = 0; k < kDraws; ++k) {
            mirage::core::PulseRng rng(0x5eed'0001ULL, k, stream);
            if (r.is_void(n_laser, n_other, rng.normal())) ++voids;
        }
        ++stream;
        const double measured = static_cast<double>(voids) / static_cast<double>(kDraws);
        const double bound =
            5.0 * std::sqrt(predicted * (1.0 - predicted) / static_cast<double>(kDraws));
        std::printf("N_laser %.2f e- (a %.2f, N_o %.0f): predicted %.5f measured %.5f bound %.5f\n",
                    n_laser, a, n_other, predicted, measured, bound);
        EXPECT_LE(std::abs(measured - predicted), bound) << target;
    }
}

TEST(VoidProbability, is_void_agrees_with_the_closed_form_threshold_for_every_z) {
    // void ⇔ |z| > √Q/a: probe z just inside and outside the threshold.
    const mp::Radiometry r = noisy_radiometry();
    const double a = r.noise_floor_electrons();
    const double n_l = 900.0, n_o = 40.0;
    const double q = (n_l / 3.0) * (n_l / 3.0) - n_l - n_o;
    const double t = std::sqrt(q) / a;
    for (double s : {1.0, -1.0}) {
        EXPECT_FALSE(r.is_void(n_l, n_o, s * t * (1.0 - 1e-9)));
        EXPECT_TRUE(r.is_void(n_l, n_o, s * t * (1.0 + 1e-9)));
    }
}
