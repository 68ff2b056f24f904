// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mirage/physics/radiometry.hpp"

using mirage::physics::monostatic_brdf;
using mirage::scene::Material;

using std::numbers::pi;

TEST(Brdf, lambertian_is_rho_over_pi_at_every_incidence) {
    Material m;
    m.reflectance = 0.37;
    for (double c : {1.0, 0.9, 0.5, 0.1, 0.01})
        EXPECT_NEAR(monostatic_brdf(m, c), 0.37 / pi, 1e-15) << c;
}

TEST(Brdf, facing_away_returns_zero) {
    Material m;
    m.retroreflective = true;
    m.specular = 0.2;
    EXPECT_EQ(monostatic_brdf(m, 0.0), 0.0);
    EXPECT_EQ(monostatic_brdf(m, -0.5), 0.0);
}

TEST(Brdf, retroreflective_is_much_larger_than_lambertian) {
    Material lam;
    lam.reflectance = 0.5;
    Material retro = lam;
    retro.retroreflective = true;
    retro.retro_gain = 100.0;
    for (double c : {1.0, 0.7, 0.3}) {
        EXPECT_NEAR(monostatic_brdf(retro, c), 0.5 / pi + 100.0, 1e-12);
        EXPECT_GT(monostatic_brdf(retro, c), 100.0 * monostatic_brdf(lam, c));
    }
}

TEST(Brdf, specular_lobe_peaks_at_normal_incidence_and_vanishes_past_45_degrees) {
    Material m;
    m.reflectance = 0.2;
    m.specular = 0.3;
    m.specular_exponent = 20.0;
    // Normal incidence: the mirror direction is the view direction, cos 2θ = 1.
    EXPECT_NEAR(monostatic_brdf(m, 1.0), 0.2 / pi + 0.3 * 22.0 / (2.0 * pi), 1e-12);
    // Closed form at θ = 10°: cos^n(2θ).
    const double th = 10.0 * pi / 180.0;
    EXPECT_NEAR(monostatic_brdf(m, std::cos(th)),
                0.2 / pi + 0.3 * 22.0 / (2.0 * pi) * std::pow(std::cos(2.0 * th), 20.0), 1e-12);
    // Strictly decreasing from 0° to 30° (beyond, cos^20(2θ) < 1e-6 of the peak and soon
    // below double resolution next to ρ/π), non-increasing to 45°, then only the diffuse part.
    double prev = monostatic_brdf(m, 1.0);
    for (int deg = 1; deg < 45; ++deg) {
        const double f = monostatic_brdf(m, std::cos(deg * pi / 180.0));
        if (deg <= 30)
            EXPECT_LT(f, prev) << deg;
        else
            EXPECT_LE(f, prev) << deg;
        prev = f;
    }
    for (int deg = 45; deg <= 89; deg += 4)
        EXPECT_NEAR(monostatic_brdf(m, std::cos(deg * pi / 180.0)), 0.2 / pi, 1e-12) << deg;
}
