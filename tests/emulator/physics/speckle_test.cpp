// SPDX-License-Identifier: Apache-2.0
// Speckle against closed forms (docs/time-resolved.md §6): the Gamma factor's mean and variance,
// and photon detection through it, whose counts are negative-binomial.
#include "mirage/physics/speckle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace {

using mirage::core::PulseRng;
using mirage::physics::speckle_factor;

TEST(Speckle, the_factor_has_mean_1_and_variance_1_over_m) {
    constexpr int kN = 200'000;
    for (const double m : {1.0, 2.5, 4.0, 20.0}) {
        double s1 = 0, s2 = 0;
        for (int i = 0; i < kN; ++i) {
            PulseRng rng(3, static_cast<std::uint64_t>(i), 4);
            const double g = speckle_factor(rng, m);
            ASSERT_GT(g, 0.0);
            s1 += g;
            s2 += g * g;
        }
        const double mean = s1 / kN, var = s2 / kN - mean * mean;
        std::printf("M = %4.1f: mean %.4f, variance %.4f against 1/M = %.4f (%+.2f %%)\n", m, mean,
                    var, 1 / m, 100 * (var * m - 1));
        EXPECT_NEAR(mean, 1.0, 4 * std::sqrt(1 / m / kN));
        EXPECT_NEAR(var * m, 1.0, 0.03);
    }
}

// A pulse expecting N̄ photo-electrons detects (≥ 1) with probability 1 − e^(−N̄g) for its speckle
// factor g: over the Gamma law that is 1 − (1 + N̄/M)^(−M), the negative-binomial's (N̄ = 2, M = 1:
// 0.667; Poisson alone 0.865).
TEST(Speckle, detection_probability_follows_the_negative_binomial) {
    constexpr int kN = 100'000;
    const double nbar = 2.0;
    for (const double m : {1.0, 4.0, 50.0}) {
        int detected = 0;
        for (int i = 0; i < kN; ++i) {
            PulseRng rng(5, static_cast<std::uint64_t>(i), 4);
            const double g = speckle_factor(rng, m);
            detected += rng.uniform() < 1 - std::exp(-nbar * g);
        }
        const double p = double(detected) / kN, want = 1 - std::pow(1 + nbar / m, -m);
        std::printf("N = 2, M = %4.1f: P(detect) %.4f against 1 - (1 + N/M)^-M = %.4f\n", m, p,
                    want);
        EXPECT_NEAR(p, want, 0.01);
    }
}

}  // namespace
