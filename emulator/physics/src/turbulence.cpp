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

namespace {

// ∫₀¹ Cn²(h(ξ))·w(1 − ξ) dξ along a straight path from h0 (ξ = 0) to h1 by Simpson's rule on 64
// intervals (the profile varies over 100 m and more; a pulse's path spans one such scale at most
// a few times).
template <class Weight>
double path_integral(const Turbulence& t, double h0_m, double h1_m, Weight w) {
    constexpr int kN = 64;
    double sum = 0;
    for (int k = 0; k <= kN; ++k) {
        const double xi = double(k) / kN, simpson = k == 0 || k == kN ? 1 : (k % 2 ? 4 : 2);
        sum += simpson * t.cn2_at(h0_m + xi * (h1_m - h0_m)) * w(1.0 - xi);
    }
    return sum / (3.0 * kN);
}

}  // namespace

double Turbulence::beam_wander_m2(double length_m, double w0_m, double h0_m, double h1_m) const {
    const double scale = std::pow(length_m, 3) / std::cbrt(w0_m);
    if (!hufnagel_valley) return 2.42 * cn2 * scale;
    return 7.26 * scale * path_integral(*this, h0_m, h1_m, [](double x) { return x * x; });
}

double Turbulence::beam_spread_m2(double length_m, double w0_m, double h0_m, double h1_m) const {
    const double scale = std::pow(length_m, 3) / std::cbrt(w0_m);
    // The long-term spread W²·1.33·σ_R²·Λ^(5/6), σ_R² = 1.23·Cn²·k^(7/6)·L^(11/6), in the far field
    // (W = 2L/(k·w0), Λ = 2L/(k·W²)) is 1.33·1.23·2^(7/6)·Cn²·L³·w0^(−1/3): k cancels. Along a
    // profile Cn² weighs as (1 − ξ)^(5/3) (ξ from the transmitter), whose integral is 3/8.
    constexpr double kLongTerm = 1.33 * 1.23 * 2.2449241 * 8.0 / 3.0;
    if (!hufnagel_valley) return (kLongTerm * 3.0 / 8.0 - 2.42) * cn2 * scale;
    return scale * path_integral(*this, h0_m, h1_m, [](double x) {
               return kLongTerm * std::pow(x, 5.0 / 3.0) - 7.26 * x * x;
           });
}

double Turbulence::image_wander_rad2(double length_m, double d_m, double h0_m, double h1_m) const {
    const double scale = length_m / std::cbrt(d_m);
    if (!hufnagel_valley) return 1.09125 * cn2 * scale;
    return 2.91 * scale *
           path_integral(*this, h0_m, h1_m, [](double x) { return std::pow(x, 5.0 / 3.0); });
}

}  // namespace mirage::physics
