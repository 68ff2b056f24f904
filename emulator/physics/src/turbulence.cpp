// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/turbulence.hpp"

#include <algorithm>
#include <cmath>

namespace mirage::physics {

double hufnagel_valley_57(double h_m) {
    const double h = std::max(0.0, h_m), v = 21.0;
    return 0.00594 * (v / 27) * (v / 27) * std::pow(1e-5 * h, 10) * std::exp(-h / 1000) +
           2.7e-16 * std::exp(-h / 1500) + 1.7e-14 * std::exp(-h / 100);
}

double Turbulence::beam_wander_m2(double length_m, double w0_m, double h0_m, double h1_m) const {
    const double scale = std::pow(length_m, 3) / std::cbrt(w0_m);
    if (!hufnagel_valley) return 2.42 * cn2 * scale;
    // ∫₀¹ Cn²(h(ξ))(1 − ξ)² dξ by Simpson's rule on 64 intervals (the profile varies over
    // 100 m and more; a pulse's path spans one such scale at most a few times).
    constexpr int kN = 64;
    double sum = 0;
    for (int k = 0; k <= kN; ++k) {
        const double xi = double(k) / kN, w = k == 0 || k == kN ? 1 : (k % 2 ? 4 : 2);
        sum += w * hufnagel_valley_57(h0_m + xi * (h1_m - h0_m)) * (1 - xi) * (1 - xi);
    }
    return 7.26 * scale * sum / (3.0 * kN);
}

}  // namespace mirage::physics
