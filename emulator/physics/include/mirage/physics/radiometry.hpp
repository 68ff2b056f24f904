// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "mirage/physics/turbulence.hpp"
#include "mirage/scene/scene.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::physics {

// Exact SI constants (2019 SI). Photon energy h·c/λ = 1.98645e-19 J at λ = 1 µm.
inline constexpr double kPlanckJouleSeconds = 6.62607015e-34;
inline constexpr double kSpeedOfLightMPerS = 299'792'458.0;
// The seed (eqs. 2–13) writes irradiance in W/(cm²·µm); Mirage uses W/(m²·µm):
// multiply a seed value by this factor (1 W/cm² = 1e4 W/m²).
inline constexpr double kPerCm2ToPerM2 = 1e4;

// Energy of one photon, J.
double photon_energy_j(double wavelength_m);

// Beer–Lambert atmosphere with a constant extinction coefficient α (m⁻¹).
struct Atmosphere {
    double extinction_per_m = 0.0;  // α at the scene's local z = 0
    // Exponential profile α(z) = α·exp(−z/H) with this H (docs/time-resolved.md §6); 0: the
    // same α everywhere.
    double scale_height_m = 0.0;
    // Kim/Kruse visibility model (docs/physics.md §3.2): α = (3.91/V)·(λ/0.55 µm)^(−q) with V in
    // km, λ in µm, q = 1.6 (V > 50 km), 1.3 (6–50 km), 0.585·V^(1/3) (< 6 km). Returns m⁻¹. Inputs
    // are SI (m) and converted here, the one boundary. Test vector: 1064 nm, 23 km → 0.0721 km⁻¹
    // = 7.21e-5 m⁻¹ (two-way transmission over 1 km 0.866). Throws ConfigError unless both inputs
    // are finite and > 0.
    static double extinction_from_visibility(double visibility_m, double wavelength_m);
    double one_way(double range_m) const {
        return std::exp(-extinction_per_m * range_m);
    }  // τ(R) = exp(−αR); monostatic two-way is τ(R)²
    // ∫α ds along a straight path of `length` from height z0 to z1 (local z): α·L for
    // homogeneous air, else α·L·e^(−z0/H)·(1 − e^(−Δ/H))/(Δ/H), Δ = z1 − z0 (→ α(z0)·L as Δ → 0).
    double optical_depth(double z0, double z1, double length) const {
        if (!(scale_height_m > 0.0)) return extinction_per_m * length;
        const double x = (z1 - z0) / scale_height_m;
        const double mean = std::abs(x) < 1e-9 ? 1.0 : -std::expm1(-x) / x;
        return extinction_per_m * length * std::exp(-z0 / scale_height_m) * mean;
    }
};

// Sun as the "other" source of docs/physics.md eqs. (6)–(10).
struct Sun {
    double elevation_rad = -1.0;  // below 0: night, no background
    double azimuth_rad = 0.0;     // clockwise from north
    // Spectral irradiance normal to the sun *at the surface* (already through the atmosphere,
    // eq. 6's E_source), W/(m²·µm). Seed values in W/(cm²·µm) × kPerCm2ToPerM2.
    double irradiance_w_m2_um = 0.0;
    bool up() const { return elevation_rad > 0.0 && irradiance_w_m2_um > 0.0; }
    // Unit vector towards the sun, world ENU (x east, y north, z up):
    // (cos e·sin a, cos e·cos a, sin e) for elevation e and azimuth a clockwise from north.
    Eigen::Vector3d to_sun_enu() const;
};

struct Environment {
    Atmosphere atmosphere;
    Sun sun;
    double path_radiance_w_m2_sr_um = 0.0;  // L_path of eq. 9, W/(m²·sr·µm)
    // Volume backscatter in waveforms (docs/time-resolved.md §6): β = α/S with this lidar ratio
    // S (sr); 0: none.
    double lidar_ratio_sr = 0.0;
    // Beam wander of every pulse (docs/time-resolved.md §6); off by default.
    Turbulence turbulence;
};

// Monostatic BRDF value (sr⁻¹) of a material seen from the source direction at incidence
// cos θ: ρ_d/π + specular·(n+2)/(2π)·cos^n(2θ)⁺ + retro_gain if retroreflective.
// Monostatic: the mirror direction of the source lies 2θ from the view direction, so the Phong
// lobe is evaluated at 2θ and peaks at normal incidence. cos θ is expected in [0, 1] (pass
// |n·d| for two-sided meshes); values ≤ 0 (surface facing away) return 0.
inline double monostatic_brdf(const scene::Material& m, double cos_incidence) {
    if (!(cos_incidence > 0.0)) return 0.0;  // facing away (or NaN): no return
    const double c = std::min(cos_incidence, 1.0);
    double f = m.reflectance / std::numbers::pi;
    if (m.specular > 0.0) {
        // Source and receiver coincide, so the mirror direction is 2θ away from the view:
        // cos 2θ = 2cos²θ − 1. (n+2)/(2π) normalises the Phong lobe.
        const double cos2 = 2.0 * c * c - 1.0;
        if (cos2 > 0.0) {
            const double n = m.specular_exponent;
            f += m.specular * (n + 2.0) / (2.0 * std::numbers::pi) * std::pow(cos2, n);
        }
    }
    if (m.retroreflective) f += m.retro_gain;
    return f;
}

// docs/physics.md eq. (2) in SI: irradiance over the spot, normal to the beam, W/m²:
// E = P·τ / (π·R²·tan²(β/2)), β the full divergence. Uses power, not spectral power: eq. 5's
// integral over the laser band is the in-band power times the filter's share (eq. M0).
// Check value (docs/physics.md §1.0): P = 1 W, τ = 1, β = 3 mrad, R = 100 m → 14.147 W/m²
// (the seed's 1.4147e-3 W/cm²). Returns 0 for R ≤ 0.
double laser_irradiance_w_m2(double power_w, double tau, double divergence_rad, double range_m);

// docs/physics.md eq. (1), monostatic, in the corrected form of docs/physics.md §1.1 (a target
// re-radiating E·Γ/(4π) W/sr into a receiver of area π·D²/4):
//     P_r = K·P_s·η_t·η_r·τ²·Γ·D² / (4π·β²·R⁴)
// (the seed prints 4 × this). With a fixed Γ (target smaller than the beam) it falls as 1/R⁴.
double range_equation_eq1_w(double peak_power_w, double range_m, double cross_section_m2,
                            double divergence_rad, double aperture_diameter_m, double eta_t,
                            double eta_r, double tau_one_way, double beam_profile_k = 1.0);
// The laser cross-section Γ that makes eq. 1 equal the radiometric chain (eqs. 2–4) for an
// extended Lambertian target that holds the whole spot inside the pixel FOV:
//     Γ = 4·ρ·cos θ·A_spot,   A_spot = π·(β·R/2)²  (beam cross-section normal to the beam,
// in eq. 1's small-angle convention, so that eq. 1's β² cancels).
// Derivation: the spot intercepts E·A_spot; its radiant intensity towards the source is
// (ρ/π)·E·cos θ·A_spot; setting that equal to E·Γ/(4π) gives Γ. Substituting Γ into eq. 1 gives
// P_s·η_t·η_r·τ²·ρ·cos θ·D²/(4R²) = closed_form_lambertian_w (under-fill) exactly; the eq. 2–4
// chain gives the same, its tan²(β/2) cancelling against Ω_spot = π·tan²(β/2).
// (Per unit surface area this is the usual Lambertian σ = 4·ρ·A·cos²θ.)
double lambertian_cross_section_m2(double reflectance, double cos_incidence, double range_m,
                                   double divergence_rad);

// docs/physics.md eqs. (2)–(13) in SI (converted at this one boundary; the paper writes cm and µm).
// Precomputes the constants of one sensor in one environment; all methods are const and
// thread-safe. Regime: the receiver collects L·A_r·min(Ω_pix, Ω_spot), which is eq. 4 when the
// spot over-fills the pixel IFOV and the under-fill form otherwise, so both fall as 1/R² on an
// extended target.
//
// Definitions (all SI; wavelengths in m except the detector band Δλ_det, which multiplies
// spectral quantities per µm and is therefore taken in µm):
//   peak power        P_s     = pulse_energy / pulse_width                         W
//   aperture area     A_r     = π·D²/4                                            m²
//   focal length      f       = F#·D                                              m
//   pixel solid angle Ω_pix   = A_pix / f²                                        sr
//   spot solid angle  Ω_spot  = π·tan²(β/2), β full divergence                    sr
//   transmission      τ(R)    = exp(−αR), each way
//   eq. 2  E   = w·P_s·η_t·τ(R) / (π·R²·tan²(β/2))                               W/m²
//   eq. 3  L   = brdf·E·cos θ₁            (brdf = ρ_d/π for a Lambertian surface)  W/(m²·sr)
//   eq. 4' P_r = L·τ(R)·η_r·A_r·min(Ω_pix, Ω_spot)                                W
//          When the spot over-fills the pixel this is eq. 4 exactly (times η_r, which the seed
//          omits): A_r·Ω_pix = π·A_pix/(4·F#²).
//   eq. 5  N_laser = P_r·pulse_width·λ·QE/(h·c)    (the pulse's energy in photo-electrons)
//   eqs. 6–10 (background fills the whole pixel FOV, spectral densities per µm):
//          N_other = τ_int·λ·QE/(h·c)·Δλ_det[µm]·η_r·A_r·Ω_pix·
//                    [ brdf_d·E_sun·max(0, cos θ₂)·τ(R) + L_path ]
//          E_sun W/(m²·µm), L_path W/(m²·sr·µm); the sun term only when Sun::up().
//   τ_int  = ReceiverParams::integration_time_s, or the pulse width when that is 0.
//   eq. 12 (first, dimensionally correct form, docs/physics.md §1.4), δE = σ₁·z, z ~ N(0, 1):
//          ΔN = sqrt((a·z)² + N_laser + N_other),
//          a  = noise_floor_e_ = τ_int·σ₁·λ·Δλ_det[µm]·A_pix·QE/(h·c),
//          σ₁ = ReceiverParams::noise_irradiance_sigma in W/(m²·µm) (the seed's W/(cm²·µm)
//          × kPerCm2ToPerM2).
//   void   N_laser < γ·ΔN.
class Radiometry {
  public:
    // Throws ConfigError naming the field unless wavelength, pulse energy and width, divergence
    // (< π), aperture, f-number and pixel area are > 0.
    Radiometry(const sensor::BeamParams& beam, const sensor::ReceiverParams& rx,
               const Environment& env);

    // Received laser power (W) from one sub-ray carrying `weight` of the pulse, hitting a
    // surface with BRDF `brdf` (sr⁻¹) at `range_m` and incidence cos θ₁ (eqs. 2–4).
    // Returns 0 for R ≤ 0 or cos θ₁ ≤ 0.
    double laser_power_w(double weight, double range_m, double brdf, double cos_incidence) const;
    // The same with the two-way transmission τ(R)² supplied, so a pulse's sub-rays can share one
    // exponential (the pipeline's hot path).
    double laser_power_w(double weight, double range_m, double brdf, double cos_incidence,
                         double tau_two_way) const;
    // Photo-electrons of the laser return (eq. 5): energy over the pulse × λη/(hc).
    double laser_electrons(double power_w) const;
    // Background photo-electrons (eqs. 6–10): sun on the surface (cos θ₂ = sun·normal, ≤ 0 → 0)
    // plus path radiance, over the detector band and τ_int. `brdf_diffuse` is ρ_d/π (sr⁻¹).
    double background_electrons(double range_m, double brdf_diffuse, double cos_sun) const;
    // The same with the one-way transmission τ(R) supplied (the pipeline shares exponentials).
    double background_electrons_tau(double brdf_diffuse, double cos_sun, double tau) const;
    // Noise-floor electrons per unit standard normal (the first term of eq. 12 with δE = σ₁).
    double noise_floor_electrons() const { return noise_floor_e_; }
    // ΔN of eq. 12 for a drawn standard normal z (δE = σ₁·z).
    double delta_n(double n_laser, double n_other, double z) const;
    // Void rule: N_laser < γ·ΔN.
    bool is_void(double n_laser, double n_other, double z) const;
    // n returns at once, equal to the calls above element by element, in loops without branches
    // that vectorise (the pipeline's hot path): out[k] = background_electrons_tau(brdf_diffuse[k],
    // cos_sun[k], tau[k]); and voids[k] = 1 if is_void(n_laser[k], n_other[k], z[k]) else 0,
    // with z = 0 when `z` is null (noise off).
    void background_electrons_many(const double* brdf_diffuse, const double* cos_sun,
                                   const double* tau, std::size_t n, double* out) const;
    void voids_many(const double* n_laser, const double* n_other, const double* z, std::size_t n,
                    double* voids) const;
    // Closed-form probability of a void over z ~ N(0, 1). With a = noise_floor_electrons():
    // void ⇔ a²z² > (N_l/γ)² − N_l − N_o =: Q; Q < 0 → 1; a = 0 → 0; Q = 0 → 1;
    // else P(|z| > √Q/a) = erfc(√Q/(a·√2)). Agrees with is_void() for every z.
    double void_probability(double n_laser, double n_other) const;
    // Closed form of the extended Lambertian target (test oracle):
    // P = P_s·η_t·η_r·τ²·ρ·cos θ·A_r/(π R²) · min(1, Ω_pix/Ω_spot).
    double closed_form_lambertian_w(double range_m, double reflectance, double cos_incidence) const;

    double peak_power_w() const { return peak_power_w_; }
    double spot_over_pixel() const { return spot_over_pixel_; }  // Ω_spot/Ω_pix
    double aperture_area_m2() const { return aperture_m2_; }
    double pixel_solid_angle_sr() const { return omega_pix_; }
    double spot_solid_angle_sr() const { return omega_spot_; }
    double integration_time_s() const { return tau_int_; }
    double photons_per_joule() const { return photons_per_joule_; }  // λ/(hc)

  private:
    sensor::BeamParams beam_;
    sensor::ReceiverParams rx_;
    Environment env_;
    double peak_power_w_ = 0, aperture_m2_ = 0, omega_pix_ = 0, omega_spot_ = 0;
    double spot_over_pixel_ = 0, photons_per_joule_ = 0, tau_int_ = 0, noise_floor_e_ = 0;
    double tan2_half_beta_ = 0, collect_sr_ = 0, background_e_per_w_ = 0;
    double filter_pass_ = 1;  // share of the laser line inside the detector's filter
};

// Per-pulse functions, defined here so the pipeline's loop inlines them.
inline double Radiometry::laser_power_w(double weight, double range_m, double brdf,
                                        double cos_incidence, double tau_two_way) const {
    if (!(range_m > 0.0) || !(cos_incidence > 0.0)) return 0.0;
    // eq. 2: irradiance over the spot, normal to the beam (one-way τ folded into τ² below);
    // eq. 3: radiance leaving the surface towards the receiver; eq. 4 (generalised): back
    // through the atmosphere into A_r over min(Ω_pix, Ω_spot).
    const double e = weight * peak_power_w_ * filter_pass_ * rx_.eta_transmitter /
                     (std::numbers::pi * range_m * range_m * tan2_half_beta_);
    const double l = brdf * e * std::min(cos_incidence, 1.0);
    return l * tau_two_way * rx_.eta_receiver * aperture_m2_ * collect_sr_;
}

inline double Radiometry::laser_power_w(double weight, double range_m, double brdf,
                                        double cos_incidence) const {
    const double tau = env_.atmosphere.one_way(range_m);
    return laser_power_w(weight, range_m, brdf, cos_incidence, tau * tau);
}

inline double Radiometry::laser_electrons(double power_w) const {
    return power_w * beam_.pulse_width_s * photons_per_joule_ * rx_.quantum_efficiency;
}
inline double Radiometry::background_electrons_tau(double brdf_diffuse, double cos_sun,
                                                   double tau) const {
    double radiance = env_.path_radiance_w_m2_sr_um;  // eq. 9
    if (env_.sun.up() && cos_sun > 0.0) {
        // eqs. 6–8: sunlit surface radiance, attenuated on the way back to the receiver.
        radiance += brdf_diffuse * env_.sun.irradiance_w_m2_um * std::min(cos_sun, 1.0) * tau;
    }
    return radiance * background_e_per_w_;  // eq. 10
}
inline double Radiometry::background_electrons(double range_m, double brdf_diffuse,
                                               double cos_sun) const {
    const bool sunlit = env_.sun.up() && cos_sun > 0.0;
    return background_electrons_tau(brdf_diffuse, cos_sun,
                                    sunlit ? env_.atmosphere.one_way(range_m) : 1.0);
}
inline double Radiometry::delta_n(double n_laser, double n_other, double z) const {
    const double floor = noise_floor_e_ * z;
    return std::sqrt(floor * floor + std::max(n_laser, 0.0) + std::max(n_other, 0.0));
}
inline bool Radiometry::is_void(double n_laser, double n_other, double z) const {
    // N_laser < γ·ΔN compared squared (both sides ≥ 0 once N_laser ≥ 0): no square root per
    // pulse. γ ≤ 0 never voids, as γ·ΔN ≤ 0 ≤ N_laser.
    if (!(n_laser >= 0.0)) return true;
    const double g = rx_.threshold_gamma;
    if (!(g > 0.0)) return false;
    const double floor = noise_floor_e_ * z;
    return n_laser * n_laser < g * g * (floor * floor + n_laser + std::max(n_other, 0.0));
}
// Documented monotonic map from photo-electrons to integer intensity:
// I = I_max · clamp(log(N/N_min) / log(N_max/N_min), 0, 1), rounded to nearest.
// N ≤ N_min (also 0, negative, NaN) → 0; N ≥ N_max → I_max (65535 or 255). If the range is
// degenerate (N_min ≤ 0 or N_max ≤ N_min) it is a step: I_max for N ≥ N_max, else 0.
struct IntensityCalibration {
    double n_min = 10.0;
    double n_max = 1e6;
    std::uint16_t to_u16(double n_laser) const;  // LAS, 0..65535
    std::uint8_t to_u8(double n_laser) const;    // vendor packets, 0..255
    // log(n_max / n_min), for callers that convert many values (one log per value instead of
    // two); to_u16(n) == to_u16(n, log_range()) exactly.
    double log_range() const { return std::log(n_max / n_min); }
    std::uint16_t to_u16(double n_laser, double log_range) const {
        // fraction ∈ [0, 1]: adding ½ and truncating rounds to nearest without a libm call.
        return static_cast<std::uint16_t>(fraction(n_laser, log_range) * 65535.0 + 0.5);
    }
    // to_u16 of n values at once, in a loop that vectorises (core::log_poly, within 2 ulp of
    // std::log, instead of a library call per value): equal to to_u16 except where a value lies
    // within a few ulp of a rounding boundary.
    void to_u16_many(const double* n_laser, std::size_t count, std::uint16_t* out) const;
    // Fraction in [0, 1] of the log-scaled range (the map above before scaling).
    double fraction(double n, double log_range) const {
        if (!(n_min > 0.0) || !(n_max > n_min)) return n >= n_max ? 1.0 : 0.0;
        if (!(n > n_min)) return 0.0;  // also 0, negative and NaN
        if (n >= n_max) return 1.0;
        return std::clamp(std::log(n / n_min) / log_range, 0.0, 1.0);
    }
};

}  // namespace mirage::physics
