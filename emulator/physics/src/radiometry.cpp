// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/radiometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "mirage/core/error.hpp"

namespace mirage::physics {
namespace {

void require_positive(const char* field, double value) {
    if (std::isfinite(value) && value > 0.0) return;
    std::ostringstream msg;
    msg << "physics: " << field << " must be finite and > 0 (got " << value << ")";
    throw ConfigError(msg.str());
}

void require_non_negative(const char* field, double value) {
    if (std::isfinite(value) && value >= 0.0) return;
    std::ostringstream msg;
    msg << "physics: " << field << " must be finite and >= 0 (got " << value << ")";
    throw ConfigError(msg.str());
}

}  // namespace

Radiometry::Radiometry(const sensor::BeamParams& beam, const sensor::ReceiverParams& rx,
                       const Environment& env)
    : beam_(beam), rx_(rx), env_(env) {
    require_positive("beam.wavelength_m", beam.wavelength_m);
    require_positive("beam.pulse_energy_j", beam.pulse_energy_j);
    require_positive("beam.pulse_width_s", beam.pulse_width_s);
    require_positive("beam.divergence_rad", beam.divergence_rad);
    require_non_negative("beam.laser_bandwidth_m", beam.laser_bandwidth_m);
    if (!(beam.divergence_rad < std::numbers::pi)) {
        std::ostringstream msg;
        msg << "physics: beam.divergence_rad must be < pi (got " << beam.divergence_rad << ")";
        throw ConfigError(msg.str());
    }
    require_positive("receiver.aperture_diameter_m", rx.aperture_diameter_m);
    require_positive("receiver.f_number", rx.f_number);
    require_positive("receiver.detector_area_m2", rx.detector_area_m2);
    require_non_negative("receiver.eta_transmitter", rx.eta_transmitter);
    require_non_negative("receiver.eta_receiver", rx.eta_receiver);
    require_non_negative("receiver.quantum_efficiency", rx.quantum_efficiency);
    require_non_negative("receiver.detector_bandwidth_m", rx.detector_bandwidth_m);
    require_non_negative("receiver.integration_time_s", rx.integration_time_s);
    require_non_negative("receiver.noise_irradiance_sigma", rx.noise_irradiance_sigma);
    require_non_negative("receiver.threshold_gamma", rx.threshold_gamma);
    require_non_negative("environment.atmosphere.extinction_per_m",
                         env.atmosphere.extinction_per_m);
    require_non_negative("environment.atmosphere.scale_height_m", env.atmosphere.scale_height_m);
    require_non_negative("environment.path_radiance_w_m2_sr_um", env.path_radiance_w_m2_sr_um);

    constexpr double pi = std::numbers::pi;
    // Eq. 5 integrates the laser's spectral power over its own band; the receiver's optical
    // filter passes only the part of a wider line that falls inside it (top-hat line and filter,
    // centred: docs/physics.md §1.2).
    const double laser_bw = beam.laser_bandwidth_m, det_bw = rx.detector_bandwidth_m;
    filter_pass_ = det_bw > 0.0 && laser_bw > det_bw ? det_bw / laser_bw : 1.0;
    peak_power_w_ = beam.pulse_energy_j / beam.pulse_width_s;
    aperture_m2_ = pi * rx.aperture_diameter_m * rx.aperture_diameter_m / 4.0;
    const double focal_m = rx.f_number * rx.aperture_diameter_m;
    omega_pix_ = rx.detector_area_m2 / (focal_m * focal_m);
    const double t = std::tan(0.5 * beam.divergence_rad);
    tan2_half_beta_ = t * t;
    omega_spot_ = pi * tan2_half_beta_;
    spot_over_pixel_ = omega_spot_ / omega_pix_;
    // The receiver sees the radiance of the spot over whichever cone is narrower.
    collect_sr_ = std::min(omega_pix_, omega_spot_);
    photons_per_joule_ = beam.wavelength_m / (kPlanckJouleSeconds * kSpeedOfLightMPerS);
    tau_int_ = rx.integration_time_s > 0.0 ? rx.integration_time_s : beam.pulse_width_s;
    // Spectral densities are per µm, so the detector band enters in µm.
    const double band_um = rx.detector_bandwidth_m * 1e6;
    // Electrons per W/(m²·sr·µm) of radiance filling the pixel FOV (eqs. 8–10).
    background_e_per_w_ = tau_int_ * photons_per_joule_ * rx.quantum_efficiency * band_um *
                          rx.eta_receiver * aperture_m2_ * omega_pix_;
    noise_floor_e_ = tau_int_ * rx.noise_irradiance_sigma * band_um * rx.detector_area_m2 *
                     rx.quantum_efficiency * photons_per_joule_;
}

double Radiometry::void_probability(double n_laser, double n_other) const {
    const double gamma = rx_.threshold_gamma;
    if (n_laser < 0.0) return 1.0;
    if (!(gamma > 0.0)) return 0.0;  // N_laser < 0 is the only void, handled above
    // N_l < γ·ΔN ⇔ (N_l/γ)² < a²z² + N_l + N_o ⇔ a²z² > Q.
    const double r = n_laser / gamma;
    const double q = r * r - n_laser - std::max(n_other, 0.0);
    const double a = noise_floor_e_;
    if (q < 0.0) return 1.0;
    if (!(a > 0.0)) return 0.0;
    if (q == 0.0) return 1.0;  // void for every z ≠ 0
    return std::erfc(std::sqrt(q) / (a * std::numbers::sqrt2));
}

double Radiometry::closed_form_lambertian_w(double range_m, double reflectance,
                                            double cos_incidence) const {
    if (!(range_m > 0.0) || !(cos_incidence > 0.0)) return 0.0;
    const double tau = env_.atmosphere.one_way(range_m);
    const double fill = std::min(1.0, omega_pix_ / omega_spot_);
    return peak_power_w_ * filter_pass_ * rx_.eta_transmitter * rx_.eta_receiver * tau * tau *
           reflectance * std::min(cos_incidence, 1.0) * aperture_m2_ /
           (std::numbers::pi * range_m * range_m) * fill;
}

void Radiometry::background_electrons_many(const double* __restrict brdf_diffuse,
                                           const double* __restrict cos_sun,
                                           const double* __restrict tau, std::size_t n,
                                           double* __restrict out) const {
    const double path = env_.path_radiance_w_m2_sr_um;
    const double sun = env_.sun.up() ? env_.sun.irradiance_w_m2_um : 0.0;  // 0: no sun term
    const double k = background_e_per_w_;
    for (std::size_t i = 0; i < n; ++i) {
        const double c = cos_sun[i];
        const double lit = brdf_diffuse[i] * sun * std::min(c, 1.0) * tau[i];
        out[i] = (path + (c > 0.0 ? lit : 0.0)) * k;
    }
}

void Radiometry::voids_many(const double* __restrict n_laser, const double* __restrict n_other,
                            const double* __restrict z, std::size_t n,
                            double* __restrict voids) const {
    // As is_void: N_laser < γ·ΔN squared; N_laser < 0 or NaN is a void, γ ≤ 0 voids nothing else.
    const double g = rx_.threshold_gamma;
    const double g2 = g > 0.0 ? g * g : 0.0;
    const double a = noise_floor_e_;
    for (std::size_t i = 0; i < n; ++i) {
        const double nl = n_laser[i];
        const double floor = z ? a * z[i] : 0.0;
        const double rhs = g2 * (floor * floor + nl + std::max(n_other[i], 0.0));
        const bool dark = !(nl >= 0.0);
        const bool below = nl * nl < rhs;
        voids[i] = (dark | below) ? 1.0 : 0.0;
    }
}

}  // namespace mirage::physics
