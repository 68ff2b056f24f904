// SPDX-License-Identifier: Apache-2.0
#include <cmath>
#include <numbers>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::sensor {
int ring_count(int n) {
    for (int k = 0;; ++k) {
        const long long count = 1 + 3LL * k * (k + 1);
        if (count == n) return k;
        if (count > n) return -1;
    }
}

bool is_hex_count(int n) { return n >= 1 && ring_count(n) >= 0; }

// Hexagonal rings (docs/physics.md §3.5, §4.4): ring j of k holds 6·j samples at radius j/k of
// `extent` beam radii (divergence/2; the 1/e² radius for a Gaussian). Each sample stands for an
// equal share of its annulus [(j − ½)Δ, (j + ½)Δ] (the outer one clipped at the outer ring, the
// centre a disc of radius Δ/2), weighted by the profile at the sample: Gaussian exp(−2r²/w²),
// top-hat 1.
std::vector<SubRay> footprint(int n, BeamProfile profile, double divergence_rad, double extent) {
    const int k = n >= 1 ? ring_count(n) : -1;
    if (k < 0)
        throw ConfigError("sensor: sub_rays: " + std::to_string(n) +
                          " is not a hexagonal count (1, 7, 19, 37, …)");
    if (!(divergence_rad >= 0) || !std::isfinite(divergence_rad))
        throw ConfigError("sensor: divergence: must be a finite angle ≥ 0");
    if (!(extent > 0 && extent <= 3) || (profile == BeamProfile::TopHat && extent != 1.0))
        throw ConfigError("sensor: beam.footprint_radius: must be in (0, 3], and 1 for a top-hat");
    std::vector<SubRay> out;
    out.reserve(static_cast<std::size_t>(n));
    out.push_back(SubRay{0.0f, 0.0f, 1.0f});
    if (k == 0) return out;

    const double pi = std::numbers::pi;
    const double beam_radius = 0.5 * divergence_rad;
    // Areas in units of Δ² (Δ = extent · beam radius / k), so a zero divergence still gives finite
    // weights.
    std::vector<double> w;
    w.reserve(out.capacity());
    w.push_back(pi * 0.25);
    for (int j = 1; j <= k; ++j) {
        const double inner = j - 0.5;
        const double outer = j == k ? double(k) : j + 0.5;
        const double area = pi * (outer * outer - inner * inner) / (6.0 * j);
        const double rel = extent * j / k;  // r / beam radius
        const double prof = profile == BeamProfile::Gaussian ? std::exp(-2.0 * rel * rel) : 1.0;
        const double r = beam_radius * rel;
        for (int i = 0; i < 6 * j; ++i) {
            const double a = 2.0 * pi * i / (6.0 * j);
            out.push_back(SubRay{static_cast<float>(r * std::cos(a)),
                                 static_cast<float>(r * std::sin(a)), 0.0f});
            w.push_back(area * prof);
        }
    }
    double sum = 0;
    for (double v : w) sum += v;
    for (std::size_t i = 0; i < out.size(); ++i) out[i].weight = static_cast<float>(w[i] / sum);
    return out;
}

double speckle_cells(const SensorModel& m) {
    if (m.receiver.speckle_cells != kSpeckleAuto) return m.receiver.speckle_cells;
    const double x = std::numbers::pi * m.receiver.aperture_diameter_m *
                     (0.5 * m.beam.divergence_rad) / (2 * m.beam.wavelength_m);
    return 1 + x * x;
}

}  // namespace mirage::sensor
