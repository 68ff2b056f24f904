// SPDX-License-Identifier: Apache-2.0
#include <cmath>
#include <numbers>

#include "mirage/physics/radiometry.hpp"

namespace mirage::physics {

double laser_irradiance_w_m2(double power_w, double tau, double divergence_rad, double range_m) {
    if (!(range_m > 0.0)) return 0.0;
    const double t = std::tan(0.5 * divergence_rad);
    return power_w * tau /
           (std::numbers::pi * range_m * range_m * t * t);  // docs/physics.md eq. (2)
}

double range_equation_eq1_w(double peak_power_w, double range_m, double cross_section_m2,
                            double divergence_rad, double aperture_diameter_m, double eta_t,
                            double eta_r, double tau_one_way, double beam_profile_k) {
    if (!(range_m > 0.0)) return 0.0;
    // docs/physics.md §1.1: the printed eq. 1 is 4 × too large for a target re-radiating E·Γ/(4π).
    const double r2 = range_m * range_m;
    return beam_profile_k * peak_power_w * eta_t * eta_r * tau_one_way * tau_one_way *
           cross_section_m2 * aperture_diameter_m * aperture_diameter_m /
           (4.0 * std::numbers::pi * divergence_rad * divergence_rad * r2 * r2);
}

double lambertian_cross_section_m2(double reflectance, double cos_incidence, double range_m,
                                   double divergence_rad) {
    const double spot_radius_m = 0.5 * divergence_rad * range_m;
    const double a_spot = std::numbers::pi * spot_radius_m * spot_radius_m;
    return 4.0 * reflectance * cos_incidence * a_spot;
}

}  // namespace mirage::physics
