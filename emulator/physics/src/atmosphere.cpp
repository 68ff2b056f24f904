// SPDX-License-Identifier: Apache-2.0
#include <cmath>
#include <sstream>

#include "mirage/core/error.hpp"
#include "mirage/physics/radiometry.hpp"

namespace mirage::physics {

double photon_energy_j(double wavelength_m) {
    return kPlanckJouleSeconds * kSpeedOfLightMPerS / wavelength_m;
}

double Atmosphere::extinction_from_visibility(double visibility_m, double wavelength_m) {
    if (!(std::isfinite(visibility_m) && visibility_m > 0.0) ||
        !(std::isfinite(wavelength_m) && wavelength_m > 0.0)) {
        std::ostringstream msg;
        msg << "physics: atmosphere: visibility_m (" << visibility_m << ") and wavelength_m ("
            << wavelength_m << ") must be finite and > 0";
        throw ConfigError(msg.str());
    }
    // The model is written for V in km and λ in µm (docs/physics.md §3.2: mixing nm/m here is the
    // HELIOS++ bug that makes extinction ≈ 8 × too weak). Convert at this boundary only.
    const double v_km = visibility_m * 1e-3;
    const double lambda_um = wavelength_m * 1e6;
    double q = 1.3;
    if (v_km > 50.0)
        q = 1.6;
    else if (v_km < 6.0)
        q = 0.585 * std::cbrt(v_km);
    const double alpha_per_km = (3.91 / v_km) * std::pow(lambda_um / 0.55, -q);
    return alpha_per_km * 1e-3;
}

Eigen::Vector3d Sun::to_sun_enu() const {
    // Azimuth clockwise from north: east component sin(a), north component cos(a).
    const double ce = std::cos(elevation_rad);
    return {ce * std::sin(azimuth_rad), ce * std::cos(azimuth_rad), std::sin(elevation_rad)};
}

}  // namespace mirage::physics
