// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Core>
#include <cstdint>

#include "mirage/scene/scene.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::physics {

// Beer–Lambert atmosphere with a constant extinction coefficient α (m⁻¹).
struct Atmosphere {
    double extinction_per_m = 0.0;
    // Kim/Kruse visibility model (physics.md §3.2): α = (3.91/V)·(λ/0.55 µm)^(−q) with V in km,
    // λ in µm, q = 1.6 (V > 50 km), 1.3 (6–50 km), 0.585·V^(1/3) (< 6 km). Returns m⁻¹.
    static double extinction_from_visibility(double visibility_m, double wavelength_m);
    double one_way(double range_m) const;   // τ(R) = exp(−αR)
};

// Sun as the "other" source of seed 001 eqs. 6–10.
struct Sun {
    double elevation_rad = -1.0;             // below 0: night, no background
    double azimuth_rad = 0.0;                // clockwise from north
    double irradiance_w_m2_um = 0.0;         // spectral irradiance normal to the sun, W/(m²·µm)
    bool up() const { return elevation_rad > 0.0 && irradiance_w_m2_um > 0.0; }
    Eigen::Vector3d to_sun_enu() const;      // unit vector, world ENU
};

struct Environment {
    Atmosphere atmosphere;
    Sun sun;
    double path_radiance_w_m2_sr_um = 0.0;   // L_path of eq. 9
};

// Monostatic BRDF value (sr⁻¹) of a material seen from the source direction at incidence
// cos θ: ρ_d/π + specular·(n+2)/(2π)·cos^n(2θ)⁺ + retro_gain if retroreflective.
double monostatic_brdf(const scene::Material& m, double cos_incidence);

// Seed 001 eqs. 2–13 in SI (converted at this one boundary; the seed writes cm and µm).
// Precomputes the constants of one sensor in one environment; all methods are const and
// thread-safe. Regime: the receiver collects L·A_r·min(Ω_pix, Ω_spot), which is eq. 4 when the
// spot over-fills the pixel IFOV and the under-fill form otherwise, so both fall as 1/R² on an
// extended target.
class Radiometry {
public:
    Radiometry(const sensor::BeamParams& beam, const sensor::ReceiverParams& rx,
               const Environment& env);

    // Received laser power (W) from one sub-ray carrying `weight` of the pulse, hitting a
    // surface with BRDF `brdf` (sr⁻¹) at `range_m` and incidence cos θ₁ (eqs. 2–4).
    double laser_power_w(double weight, double range_m, double brdf, double cos_incidence) const;
    // Photo-electrons of the laser return (eq. 5): energy over the pulse × λη/(hc).
    double laser_electrons(double power_w) const;
    // Background photo-electrons (eqs. 6–10): sun on the surface (cos θ₂ = sun·normal, ≤ 0 → 0)
    // plus path radiance, over the detector band and τ_int.
    double background_electrons(double range_m, double brdf_diffuse, double cos_sun) const;
    // Noise-floor electrons per unit standard normal (the first term of eq. 12 with δE = σ₁).
    double noise_floor_electrons() const { return noise_floor_e_; }
    // ΔN of eq. 12 for a drawn standard normal z (δE = σ₁·z).
    double delta_n(double n_laser, double n_other, double z) const;
    // Void rule: N_laser < γ·ΔN.
    bool is_void(double n_laser, double n_other, double z) const;
    // Closed-form probability of a void over z ~ N(0, 1).
    double void_probability(double n_laser, double n_other) const;
    // Closed form of the extended Lambertian target (test oracle):
    // P = P_s·η_t·η_r·τ²·ρ·cos θ·A_r/(π R²) when the pixel FOV holds the spot.
    double closed_form_lambertian_w(double range_m, double reflectance, double cos_incidence) const;

    double peak_power_w() const { return peak_power_w_; }
    double spot_over_pixel() const { return spot_over_pixel_; }  // Ω_spot/Ω_pix

private:
    sensor::BeamParams beam_;
    sensor::ReceiverParams rx_;
    Environment env_;
    double peak_power_w_ = 0, aperture_m2_ = 0, omega_pix_ = 0, omega_spot_ = 0;
    double spot_over_pixel_ = 0, photons_per_joule_ = 0, tau_int_ = 0, noise_floor_e_ = 0;
};

// Documented monotonic map from photo-electrons to integer intensity:
// I = I_max · clamp(log(N/N_min) / log(N_max/N_min), 0, 1), rounded.
struct IntensityCalibration {
    double n_min = 10.0;
    double n_max = 1e6;
    std::uint16_t to_u16(double n_laser) const;   // LAS, 0..65535
    std::uint8_t to_u8(double n_laser) const;     // vendor packets, 0..255
};

}  // namespace mirage::physics
