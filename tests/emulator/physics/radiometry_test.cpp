// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/radiometry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include "mirage/core/error.hpp"
#include "test_units.hpp"

namespace mp = mirage::physics;
using mirage::sensor::BeamParams;
using mirage::sensor::ReceiverParams;

namespace {

constexpr double kPi = std::numbers::pi;
using mirage::test::kDeg;

BeamParams test_beam() {
    BeamParams b;
    b.wavelength_m = 905e-9;
    b.pulse_energy_j = 1e-7;
    b.pulse_width_s = 5e-9;  // P_s = 20 W
    b.divergence_rad = 3e-3;
    return b;
}

// detector_area 1e-7 m² at D = 25 mm, F/1: Ω_pix = 1.6e-4 sr ≫ Ω_spot = 7.07e-6 sr (spot inside
// the pixel FOV, "under-fill"); 1e-10 m² gives Ω_pix = 1.6e-7 sr (spot over-fills the pixel).
ReceiverParams test_receiver(double detector_area_m2) {
    ReceiverParams r;
    r.aperture_diameter_m = 0.025;
    r.f_number = 1.0;
    r.detector_area_m2 = detector_area_m2;
    r.eta_transmitter = 0.9;
    r.eta_receiver = 0.8;
    r.quantum_efficiency = 0.7;
    r.detector_bandwidth_m = 20e-9;
    return r;
}

mp::Environment hazy() {
    mp::Environment env;
    env.atmosphere.extinction_per_m = mp::Atmosphere::extinction_from_visibility(5e3, 905e-9);
    return env;
}

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

}  // namespace

TEST(Radiometry, eq2_irradiance_matches_check_value_in_si_and_seed_units) {
    // docs/physics.md §1.0: φ = 1 W, τ = 1, β = 3 mrad, R = 100 m → 14.147 W/m² = 1.4147e-3 W/cm².
    const double e = mp::laser_irradiance_w_m2(1.0, 1.0, 3e-3, 100.0);
    std::printf("eq.2 check: E = %.6f W/m^2 = %.6e W/cm^2\n", e, e / mp::kPerCm2ToPerM2);
    EXPECT_NEAR(e, 14.147, 5e-4);
    // Same number from the seed's own cm units: R = 1e4 cm.
    const double t = std::tan(1.5e-3);
    const double e_cm = 1.0 / (kPi * 1e4 * 1e4 * t * t);
    EXPECT_NEAR(e_cm, 1.4147e-3, 5e-8);
    EXPECT_NEAR(e / mp::kPerCm2ToPerM2, e_cm, 1e-12 * e_cm);
}

TEST(Radiometry, photon_energy_is_hc_over_lambda) {
    const double ej = mp::photon_energy_j(1e-6);
    std::printf("h c / 1 um = %.8e J\n", ej);
    EXPECT_NEAR(ej, 1.98645e-19, 1e-24);
    const mp::Radiometry r(test_beam(), test_receiver(1e-7), {});
    EXPECT_NEAR(r.photons_per_joule() * mp::photon_energy_j(905e-9), 1.0, 1e-15);
}

TEST(Radiometry, derived_constants_follow_their_definitions) {
    const mp::Radiometry r(test_beam(), test_receiver(1e-7), {});
    EXPECT_NEAR(r.peak_power_w(), 20.0, 1e-12);
    EXPECT_NEAR(r.aperture_area_m2(), kPi * 0.025 * 0.025 / 4.0, 1e-18);
    EXPECT_NEAR(r.pixel_solid_angle_sr(), 1e-7 / (0.025 * 0.025), 1e-18);
    EXPECT_NEAR(r.spot_solid_angle_sr(), kPi * std::pow(std::tan(1.5e-3), 2), 1e-18);
    EXPECT_NEAR(r.integration_time_s(), 5e-9, 1e-24);  // 0 → pulse width
    ReceiverParams rx = test_receiver(1e-7);
    rx.integration_time_s = 2e-6;
    EXPECT_EQ(mp::Radiometry(test_beam(), rx, {}).integration_time_s(), 2e-6);
}

TEST(Radiometry, eq4_equals_pixel_solid_angle_form_when_spot_overfills_pixel) {
    // Identity A_r·Ω_pix = π·A_pix/(4·F#²) for several optics.
    for (double d : {0.01, 0.025, 0.1})
        for (double fn : {0.8, 1.0, 2.8})
            for (double apix : {1e-10, 4e-9, 1e-7}) {
                ReceiverParams rx = test_receiver(apix);
                rx.aperture_diameter_m = d;
                rx.f_number = fn;
                const mp::Radiometry r(test_beam(), rx, {});
                EXPECT_NEAR(r.aperture_area_m2() * r.pixel_solid_angle_sr(),
                            kPi * apix / (4.0 * fn * fn), 1e-12 * kPi * apix / (4.0 * fn * fn));
            }
    // laser_power_w in the over-fill regime equals η_r × seed eq. 4 evaluated in the seed's
    // own cm units (R in cm, A_pix in cm², E in W/cm²).
    const mp::Environment env = hazy();
    const mp::Radiometry r(test_beam(), test_receiver(1e-10), env);
    ASSERT_GT(r.spot_over_pixel(), 1.0);
    const double rho = 0.3;
    for (double range_m : {2.0, 35.0, 120.0}) {
        const double cos1 = std::cos(25.0 * kDeg);
        const double tau = env.atmosphere.one_way(range_m);
        const double r_cm = 100.0 * range_m;
        const double t = std::tan(1.5e-3);
        const double e_cm = 20.0 * 0.9 * tau / (kPi * r_cm * r_cm * t * t);  // eq. 2
        const double apix_cm2 = 1e-10 * 1e4;
        const double phi = rho * e_cm / (4.0 * 1.0 * 1.0) * cos1 * apix_cm2 * tau;  // eq. 4
        EXPECT_LT(rel(r.laser_power_w(1.0, range_m, rho / kPi, cos1), 0.8 * phi), 1e-12) << range_m;
    }
}

TEST(Radiometry, received_power_matches_lambertian_closed_form_in_both_regimes) {
    const mp::Environment env = hazy();
    for (double apix : {1e-7, 1e-10}) {
        const mp::Radiometry r(test_beam(), test_receiver(apix), env);
        const bool overfill = apix < 1e-8;
        std::printf("A_pix %.0e: Omega_spot/Omega_pix = %.4g\n", apix, r.spot_over_pixel());
        EXPECT_EQ(r.spot_over_pixel() > 1.0, overfill);
        // Independent oracle from the raw parameters.
        const double a_r = kPi * 0.025 * 0.025 / 4.0;
        const double omega_pix = apix / (0.025 * 0.025);
        const double omega_spot = kPi * std::pow(std::tan(1.5e-3), 2);
        const double fill = std::min(1.0, omega_pix / omega_spot);
        double worst = 0.0;
        int n = 0;
        for (int range = 1; range <= 200; ++range) {
            for (int deg = 0; deg <= 80; deg += 5) {
                const double rho = 0.05 + 0.9 * (deg / 80.0);
                const double c = std::cos(deg * kDeg);
                const double tau = std::exp(-env.atmosphere.extinction_per_m * range);
                const double oracle =
                    20.0 * 0.9 * 0.8 * tau * tau * rho * c * a_r / (kPi * range * range) * fill;
                const double p = r.laser_power_w(1.0, range, rho / kPi, c);
                worst = std::max(worst, rel(p, oracle));
                ASSERT_LE(rel(p, oracle), 1e-3) << range << " m " << deg << " deg";
                ASSERT_LE(rel(r.closed_form_lambertian_w(range, rho, c), oracle), 1e-12);
                ++n;
            }
        }
        std::printf("  %d cases, worst relative error %.3e\n", n, worst);
    }
}

TEST(Radiometry, extended_target_falls_as_inverse_square_and_carries_two_way_tau) {
    const mp::Radiometry vac(test_beam(), test_receiver(1e-7), {});
    const double p10 = vac.laser_power_w(1.0, 10.0, 0.5 / kPi, 1.0);
    EXPECT_NEAR(vac.laser_power_w(1.0, 20.0, 0.5 / kPi, 1.0) / p10, 0.25, 1e-14);
    EXPECT_NEAR(vac.laser_power_w(0.25, 10.0, 0.5 / kPi, 1.0) / p10, 0.25, 1e-14);  // weight
    for (double alpha : {1e-5, 7.21e-5, 1e-3}) {
        mp::Environment env;
        env.atmosphere.extinction_per_m = alpha;
        const mp::Radiometry r(test_beam(), test_receiver(1e-7), env);
        for (double range : {5.0, 80.0, 1500.0})
            EXPECT_NEAR(
                r.laser_power_w(1.0, range, 0.1, 0.8) / vac.laser_power_w(1.0, range, 0.1, 0.8),
                std::exp(-2.0 * alpha * range), 1e-12);
    }
    EXPECT_EQ(vac.laser_power_w(1.0, 0.0, 0.1, 1.0), 0.0);
    EXPECT_EQ(vac.laser_power_w(1.0, 10.0, 0.1, -0.2), 0.0);
}

TEST(Radiometry, eq1_with_lambertian_cross_section_equals_radiometric_chain) {
    // Corrected eq. 1 (docs/physics.md §1.1) with Γ = 4·ρ·cos θ·π(βR/2)² equals the closed form and
    // the eq. 2–4 chain to rounding: with the spot inside the pixel FOV the chain collects over
    // Ω_spot = π·tan²(β/2), which cancels eq. 2's tan²(β/2), as eq. 1's β² cancels in Γ.
    const mp::Environment env = hazy();
    const mp::Radiometry r(test_beam(), test_receiver(1e-7), env);
    ASSERT_LT(r.spot_over_pixel(), 1.0);
    double worst = 0.0;
    for (double range : {1.0, 17.0, 60.0, 200.0}) {
        for (double deg : {0.0, 30.0, 70.0}) {
            const double c = std::cos(deg * kDeg);
            const double rho = 0.42;
            const double gamma = mp::lambertian_cross_section_m2(rho, c, range, 3e-3);
            const double eq1 = mp::range_equation_eq1_w(20.0, range, gamma, 3e-3, 0.025, 0.9, 0.8,
                                                        env.atmosphere.one_way(range));
            EXPECT_LT(rel(eq1, r.closed_form_lambertian_w(range, rho, c)), 1e-12);
            const double chain = r.laser_power_w(1.0, range, rho / kPi, c);
            worst = std::max(worst, rel(eq1, chain));
            EXPECT_LT(rel(eq1, chain), 1e-12);
        }
    }
    std::printf("eq.1 vs eq.2-4 chain: worst relative difference %.3e\n", worst);
    // Fixed cross-section (point target): 1/R⁴, and K scales linearly.
    const double p1 = mp::range_equation_eq1_w(20.0, 10.0, 0.01, 3e-3, 0.025, 0.9, 0.8, 1.0);
    const double p2 = mp::range_equation_eq1_w(20.0, 20.0, 0.01, 3e-3, 0.025, 0.9, 0.8, 1.0);
    EXPECT_NEAR(p2 / p1, 1.0 / 16.0, 1e-14);
    EXPECT_NEAR(mp::range_equation_eq1_w(20.0, 10.0, 0.01, 3e-3, 0.025, 0.9, 0.8, 1.0, 0.5) / p1,
                0.5, 1e-14);
    // Absolute value of the corrected form: K·P_s·η_t·η_r·τ²·Γ·D²/(4π·β²·R⁴).
    EXPECT_NEAR(p1, 20.0 * 0.9 * 0.8 * 0.01 * 0.025 * 0.025 / (4.0 * kPi * 9e-6 * 1e4), 1e-12 * p1);
}

TEST(Radiometry, laser_electrons_are_pulse_energy_in_photoelectrons) {
    const mp::Radiometry r(test_beam(), test_receiver(1e-7), {});
    const double p = 3.7e-6;
    const double expected = p * 5e-9 * 905e-9 * 0.7 / (6.62607015e-34 * 299792458.0);
    EXPECT_NEAR(r.laser_electrons(p), expected, 1e-12 * expected);
    std::printf("N_laser(3.7 uW, 5 ns, 905 nm, QE 0.7) = %.4f e-\n", r.laser_electrons(p));
}

TEST(Radiometry, background_is_path_radiance_only_at_night_and_adds_sun_by_day) {
    ReceiverParams rx = test_receiver(1e-7);
    rx.integration_time_s = 1e-6;
    const double a_r = kPi * 0.025 * 0.025 / 4.0;
    const double omega_pix = 1e-7 / (0.025 * 0.025);
    const double e_per_w = 1e-6 * 905e-9 * 0.7 / (6.62607015e-34 * 299792458.0) * 0.02;  // ·Δλ µm
    const double brdf_d = 0.4 / kPi;
    const double range = 50.0;

    mp::Environment night = hazy();
    night.sun = mp::Sun{-5.0 * kDeg, 0.0, 900.0};
    EXPECT_EQ(mp::Radiometry(test_beam(), rx, night).background_electrons(range, brdf_d, 0.9), 0.0);
    night.path_radiance_w_m2_sr_um = 2.0;
    const double path_only = e_per_w * 2.0 * 0.8 * a_r * omega_pix;
    const double n_night =
        mp::Radiometry(test_beam(), rx, night).background_electrons(range, brdf_d, 0.9);
    EXPECT_LT(rel(n_night, path_only), 1e-12);

    mp::Environment day = night;
    day.sun = mp::Sun{40.0 * kDeg, 120.0 * kDeg, 900.0};
    const mp::Radiometry r(test_beam(), rx, day);
    const double tau = day.atmosphere.one_way(range);
    const double sun_term = e_per_w * brdf_d * 900.0 * 0.9 * tau * 0.8 * a_r * omega_pix;
    const double n_day = r.background_electrons(range, brdf_d, 0.9);
    std::printf("background: night %.4g e-, day %.4g e- (tau_int 1 us)\n", n_night, n_day);
    EXPECT_GT(n_day, n_night);
    EXPECT_LT(rel(n_day, sun_term + path_only), 1e-12);
    // Surface turned away from the sun: path radiance only.
    EXPECT_LT(rel(r.background_electrons(range, brdf_d, -0.3), path_only), 1e-12);
}

TEST(Radiometry, noise_floor_uses_first_form_of_eq12_in_si) {
    ReceiverParams rx = test_receiver(1e-7);
    rx.integration_time_s = 1e-6;
    // σ₁ = 1e-4 W/(cm²·µm) in the seed's units.
    rx.noise_irradiance_sigma = 1e-4 * mp::kPerCm2ToPerM2;
    const mp::Radiometry r(test_beam(), rx, {});
    const double expected =
        1e-6 * 1.0 * 905e-9 * 0.02 * 1e-7 * 0.7 / (6.62607015e-34 * 299792458.0);
    EXPECT_LT(rel(r.noise_floor_electrons(), expected), 1e-12);
    // Same number in the seed's units: λ, Δλ in µm, A_pix in cm², c in µm/s.
    const double seed_units =
        1e-6 * 1e-4 * 0.905 * 0.02 * (1e-7 * 1e4) * 0.7 / (6.62607015e-34 * 2.99792458e14);
    EXPECT_LT(rel(r.noise_floor_electrons(), seed_units), 1e-12);
    std::printf("noise floor a = %.4f e- per unit z\n", r.noise_floor_electrons());
    // ΔN = sqrt((a z)² + N_l + N_o).
    const double a = r.noise_floor_electrons();
    EXPECT_NEAR(r.delta_n(100.0, 50.0, 1.3), std::sqrt(a * a * 1.69 + 150.0), 1e-12);
}

TEST(Radiometry, more_background_gives_larger_delta_n_and_more_voids) {
    ReceiverParams rx = test_receiver(1e-7);
    rx.integration_time_s = 1e-6;
    rx.noise_irradiance_sigma = 1e-3;  // W/(m²·µm) → a ≈ 6.4 e- per unit z
    const mp::Radiometry r(test_beam(), rx, {});
    for (double z : {0.0, 0.5, -2.0}) {
        EXPECT_LT(r.delta_n(400.0, 10.0, z), r.delta_n(400.0, 1000.0, z));
        EXPECT_LT(r.delta_n(400.0, 1000.0, z), r.delta_n(400.0, 1e5, z));
    }
    // a ≈ 6.4 e-: at N_l = 120 the margin is ≈ 6 σ with 10 e- of background, ≈ 3.4 σ with 1000,
    // and negative with 1e5 (always void).
    const double p_low = r.void_probability(120.0, 10.0);
    const double p_mid = r.void_probability(120.0, 1000.0);
    std::printf("void probability at N_l = 120: %.3e (N_o 10), %.3e (N_o 1000)\n", p_low, p_mid);
    EXPECT_GT(p_low, 0.0);
    EXPECT_LT(p_low, p_mid);
    EXPECT_LT(p_mid, 1e-2);
    EXPECT_EQ(r.void_probability(120.0, 1e5), 1.0);
}

// The pipeline's batched forms must give exactly the scalar ones, edge values included: sun up and
// down, path radiance, cos θ₂ ≤ 0 / > 1 / NaN, N_laser negative or NaN, γ ≤ 0, noise on and off.
TEST(Radiometry, batched_background_and_voids_equal_the_scalar_forms) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> cos_sun{1.0, 0.5, 0.0, -0.3, 1.2, nan, 0.01, 0.9};
    const std::vector<double> brdf{0.1, 0.3, 0.2, 0.05, 0.15, 0.2, 0.0, 32.0};
    const std::vector<double> tau{1.0, 0.9, 0.5, 0.99, 0.7, 0.8, 0.6, 0.95};
    const std::vector<double> n_laser{400.0, 120.0, 0.0, -5.0, nan, 1e6, 3.0, 50.0};
    const std::vector<double> z{0.0, 1.5, -2.0, 0.3, 4.0, -0.7, 6.0, -6.0};
    const std::size_t n = cos_sun.size();
    std::size_t voids_seen = 0;
    for (double elevation : {0.6, -0.2}) {
        for (double path : {0.0, 40.0}) {
            for (double gamma : {1.0, 3.0, 0.0}) {
                mp::Environment env;
                env.sun.elevation_rad = elevation;
                env.sun.irradiance_w_m2_um = 700.0;
                env.path_radiance_w_m2_sr_um = path;
                ReceiverParams rx = test_receiver(1e-7);
                rx.noise_irradiance_sigma = 1e-3;
                rx.threshold_gamma = gamma;
                const mp::Radiometry r(test_beam(), rx, env);
                std::vector<double> other(n), voids(n), quiet(n);
                r.background_electrons_many(brdf.data(), cos_sun.data(), tau.data(), n,
                                            other.data());
                r.voids_many(n_laser.data(), other.data(), z.data(), n, voids.data());
                r.voids_many(n_laser.data(), other.data(), nullptr, n, quiet.data());
                for (std::size_t k = 0; k < n; ++k) {
                    EXPECT_EQ(other[k], r.background_electrons_tau(brdf[k], cos_sun[k], tau[k]))
                        << k;
                    EXPECT_EQ(voids[k], r.is_void(n_laser[k], other[k], z[k]) ? 1.0 : 0.0) << k;
                    EXPECT_EQ(quiet[k], r.is_void(n_laser[k], other[k], 0.0) ? 1.0 : 0.0) << k;
                    voids_seen += voids[k] != 0.0;
                }
            }
        }
    }
    EXPECT_GT(voids_seen, 12u);  // the cases exercise both outcomes
    EXPECT_LT(voids_seen, 12u * n);
}

TEST(Radiometry, rejects_invalid_parameters_naming_the_field) {
    BeamParams b = test_beam();
    b.pulse_width_s = 0.0;
    try {
        mp::Radiometry r(b, test_receiver(1e-7), {});
        FAIL() << "no throw";
    } catch (const mirage::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("beam.pulse_width_s"), std::string::npos);
    }
    ReceiverParams rx = test_receiver(0.0);
    EXPECT_THROW(mp::Radiometry(test_beam(), rx, {}), mirage::ConfigError);
}

// Eq. 5 over the laser's band: a filter narrower than the laser line passes Δλ_det/Δλ_laser of
// it; a wider filter passes all of it (the presets' case).
TEST(Radiometry, a_filter_narrower_than_the_laser_line_passes_its_share_of_it) {
    const ReceiverParams rx = test_receiver(1e-7);  // 20 nm filter
    auto with_line = [&](double laser_bw_m) {
        BeamParams b = test_beam();
        b.laser_bandwidth_m = laser_bw_m;
        return mp::Radiometry(b, rx, mp::Environment{}).laser_power_w(1.0, 50.0, 0.1, 1.0);
    };
    ASSERT_DOUBLE_EQ(rx.detector_bandwidth_m, 20e-9);
    const double full = with_line(5e-9);
    EXPECT_GT(full, 0.0);
    EXPECT_DOUBLE_EQ(with_line(20e-9), full);
    EXPECT_DOUBLE_EQ(with_line(40e-9), 0.5 * full);
    EXPECT_DOUBLE_EQ(with_line(80e-9), 0.25 * full);
    BeamParams bad = test_beam();
    bad.laser_bandwidth_m = -1e-9;
    EXPECT_THROW(mp::Radiometry(bad, rx, mp::Environment{}), mirage::ConfigError);
}
