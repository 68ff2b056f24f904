// SPDX-License-Identifier: Apache-2.0
// Turbulence against closed forms (docs/time-resolved.md §6): the Hufnagel–Valley 5/7 profile
// gives its name's r0 ≈ 5 cm and θ0 ≈ 7 µrad at 0.5 µm, and the beam wander of a constant Cn²
// and of the profile follow Andrews & Phillips.
#include "mirage/physics/turbulence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace {

using mirage::physics::hufnagel_valley_57;
using mirage::physics::Turbulence;

// Zenith from the ground to 30 km at λ = 0.5 µm: r0 = (0.423·k²·∫Cn² dh)^(−3/5) and the
// isoplanatic angle θ0 = (2.914·k²·∫Cn²·h^(5/3) dh)^(−3/5), midpoint sums on 1 m steps.
TEST(Turbulence, hufnagel_valley_57_gives_r0_5_cm_and_theta0_7_urad) {
    double m0 = 0, m53 = 0;
    for (int i = 0; i < 30'000; ++i) {
        const double h = i + 0.5, c = hufnagel_valley_57(h);
        m0 += c;
        m53 += c * std::pow(h, 5.0 / 3.0);
    }
    const double k = 2 * std::numbers::pi / 0.5e-6;
    const double r0 = std::pow(0.423 * k * k * m0, -0.6);
    const double theta0 = std::pow(2.914 * k * k * m53, -0.6);
    std::printf("HV 5/7: r0 %.2f cm, theta0 %.2f urad at 0.5 um\n", r0 * 100, theta0 * 1e6);
    EXPECT_NEAR(r0, 0.05, 0.05 * 0.02);
    EXPECT_NEAR(theta0, 7e-6, 7e-6 * 0.02);
    EXPECT_NEAR(hufnagel_valley_57(0), 1.7e-14 + 2.7e-16, 1e-20);
    EXPECT_EQ(hufnagel_valley_57(-5), hufnagel_valley_57(0));
}

// ⟨r_c²⟩ = 2.42·Cn²·L³·w0^(−1/3): 1.06 cm rms over 1 km with Cn² = 1e-14 and w0 = 1 cm; the
// profile's path integral reduces to it on a level path (Cn² the profile's at that height) and
// weighs the transmitter's end most: a beam sent up from the ground wanders more than one sent
// down to it (the strong turbulence is near its start).
TEST(Turbulence, beam_wander_follows_the_weak_turbulence_law) {
    Turbulence constant;
    constant.cn2 = 1e-14;
    const double rc2 = constant.beam_wander_m2(1000, 0.01, 0, 0);
    std::printf("beam wander over 1 km, Cn2 1e-14, w0 1 cm: %.3f cm rms\n", std::sqrt(rc2) * 100);
    EXPECT_NEAR(rc2, 2.42e-14 * 1e9 / std::cbrt(0.01), 1e-12);
    EXPECT_NEAR(std::sqrt(rc2), 0.0106, 0.0001);
    Turbulence hv;
    hv.hufnagel_valley = true;
    Turbulence level;
    level.cn2 = hufnagel_valley_57(50);
    EXPECT_NEAR(hv.beam_wander_m2(800, 0.01, 50, 50) / level.beam_wander_m2(800, 0.01, 50, 50), 1.0,
                1e-9);
    EXPECT_GT(hv.beam_wander_m2(1500, 0.01, 0, 1000), hv.beam_wander_m2(1500, 0.01, 1000, 0));
    EXPECT_FALSE(Turbulence{}.on());
}

}  // namespace
