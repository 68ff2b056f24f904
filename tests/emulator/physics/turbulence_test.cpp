// SPDX-License-Identifier: Apache-2.0
// Turbulence against closed forms (docs/time-resolved.md §6): the Hufnagel–Valley 5/7 profile
// gives its name's r0 ≈ 5 cm and θ0 ≈ 7 µrad at 0.5 µm, and the beam wander, the short-term beam
// spread and the image wander of a constant Cn² and of the profile follow Andrews & Phillips.
#include "mirage/physics/turbulence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace {

using mirage::physics::hufnagel_valley_57;
using mirage::physics::Turbulence;

// A law of the profile (a member of Turbulence taking length, size, h0, h1) on a level path at
// 50 m equals the constant law with the profile's Cn² there (within `tol`: Simpson's rule), and
// the path from the ground up gets more than the path down to it.
template <class Law>
void check_profile(Law law, double size_m, double tol) {
    Turbulence hv;
    hv.hufnagel_valley = true;
    Turbulence level;
    level.cn2 = hufnagel_valley_57(50);
    EXPECT_NEAR((hv.*law)(800, size_m, 50, 50) / (level.*law)(800, size_m, 50, 50), 1.0, tol);
    EXPECT_GT((hv.*law)(1500, size_m, 0, 1000), (hv.*law)(1500, size_m, 1000, 0));
}

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
    check_profile(&Turbulence::beam_wander_m2, 0.01, 1e-9);
    EXPECT_FALSE(Turbulence{}.on());
}

// The short-term spread from the Gaussian-beam parameters of a collimated beam (Andrews &
// Phillips): W = w0·√(1 + Λ0²), Λ = Λ0/(1 + Λ0²), Λ0 = 2L/(k·w0²), σ_R²
// = 1.23·Cn²·k^(7/6)·L^(11/6), W_LT² = W²·(1 + 1.33·σ_R²·Λ^(5/6)) and W_ST² = W_LT² − ⟨r_c²⟩. At
// 1064 nm over 5 km from w0 = 1 cm (Λ0 ≈ 17) the far-field law Mirage uses is within 1 % of W_ST² −
// W²; the profile reduces to it on a level path and weighs the transmitter's end most.
TEST(Turbulence, beam_spread_is_the_long_term_spot_less_the_wander) {
    const double k = 2 * std::numbers::pi / 1.064e-6, l = 5000, w0 = 0.01, cn2 = 1e-15;
    const double lam0 = 2 * l / (k * w0 * w0);
    const double w2 = w0 * w0 * (1 + lam0 * lam0), lam = lam0 / (1 + lam0 * lam0);
    const double sigma_r2 = 1.23 * cn2 * std::pow(k, 7.0 / 6.0) * std::pow(l, 11.0 / 6.0);
    const double want =
        w2 * 1.33 * sigma_r2 * std::pow(lam, 5.0 / 6.0) - 2.42 * cn2 * l * l * l / std::cbrt(w0);
    Turbulence constant;
    constant.cn2 = cn2;
    const double got = constant.beam_spread_m2(l, w0, 0, 0);
    std::printf(
        "short-term spread over 5 km, Cn2 1e-15, w0 1 cm: W_ST^2 - W^2 %.4e m2, Gaussian "
        "beam %.4e m2 (%+.2f %%; W %.3f m, sigma_R^2 %.3f)\n",
        got, want, 100 * (got / want - 1), std::sqrt(w2), sigma_r2);
    EXPECT_NEAR(got / want, 1.0, 0.01);
    // (Simpson's rule on (1 − ξ)^(5/3), not smooth at the target's end: 1e-5.)
    check_profile(&Turbulence::beam_spread_m2, 0.01, 1e-5);
}

// The angle of arrival of a spherical wave: ⟨β²⟩ = 2.91·d^(−1/3)·∫₀^L Cn²(z)·(z/L)^(5/3) dz per
// axis, z from the source, = 1.09·Cn²·L·d^(−1/3) for a constant Cn² (3/8 of the plane wave's):
// 6.11 µrad rms over 1 km with Cn² = 1e-14 and d = 2.5 cm. The receiver's end weighs most, so a
// receiver on the ground looking up sees its image wander more than one looking down.
TEST(Turbulence, image_wander_follows_the_spherical_wave_law) {
    Turbulence constant;
    constant.cn2 = 1e-14;
    const double b2 = constant.image_wander_rad2(1000, 0.025, 0, 0);
    std::printf("image wander over 1 km, Cn2 1e-14, D 2.5 cm: %.3f urad rms per axis\n",
                std::sqrt(b2) * 1e6);
    EXPECT_NEAR(b2, 2.91 * 3.0 / 8.0 * 1e-14 * 1000 / std::cbrt(0.025), 1e-20);
    EXPECT_NEAR(std::sqrt(b2), 6.11e-6, 0.01e-6);
    check_profile(&Turbulence::image_wander_rad2, 0.025, 1e-5);
}

}  // namespace
