// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cmath>
#include <numbers>

#include "mirage/physics/radiometry.hpp"

namespace mirage::physics {

double monostatic_brdf(const scene::Material& m, double cos_incidence) {
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

}  // namespace mirage::physics
