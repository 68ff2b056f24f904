// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/oscillating_mirror.hpp"

#include <cmath>
#include <numbers>

#include "mirage/core/error.hpp"
#include "scan_math.hpp"

namespace mirage::sensor {

OscillatingMirrorPattern::OscillatingMirrorPattern(AirborneConfig config)
    : AirbornePattern(config) {
    if (config_.kind != AirborneKind::Sawtooth && config_.kind != AirborneKind::Sine)
        throw ConfigError("sensor: airborne: oscillating mirror needs pattern sawtooth or sine");
}

std::string OscillatingMirrorPattern::kind() const {
    return config_.kind == AirborneKind::Sine ? "oscillating-mirror-sine"
                                              : "oscillating-mirror-sawtooth";
}

double OscillatingMirrorPattern::line_of(std::uint64_t k) const {
    const double x = cycles(k);
    // Sawtooth lines start at the turning points −F/2 (x integer) and +F/2 (x half-integer);
    // sine turning points are at x = ¼ + n/2.
    return config_.kind == AirborneKind::Sine ? std::floor(2.0 * x + 0.5) : std::floor(2.0 * x);
}

void OscillatingMirrorPattern::steer(std::uint64_t k, PulseSpec& p) const {
    const double x = cycles(k);
    const double fov = config_.fov_deg;
    double theta_deg;
    if (config_.kind == AirborneKind::Sine) {
        const double w = 2.0 * std::numbers::pi * x;
        theta_deg = 0.5 * fov * std::sin(w);
        p.scan_direction = std::cos(w) > 0 ? 1 : 0;
    } else {
        const double phase = x - std::floor(x);
        if (phase < 0.5) {
            theta_deg = -0.5 * fov + 2.0 * fov * phase;
            p.scan_direction = 1;
        } else {
            theta_deg = 0.5 * fov - 2.0 * fov * (phase - 0.5);
            p.scan_direction = 0;
        }
    }
    const double th = theta_deg * std::numbers::pi / 180.0;
    double sin_th = 0, cos_th = 1;
    detail::small_sincos(th, sin_th, cos_th);
    p.dir = Eigen::Vector3f(0.0f, static_cast<float>(-sin_th), static_cast<float>(-cos_th));
    p.scan_angle_deg = static_cast<float>(theta_deg);
    p.edge_of_flight_line = line_of(k + 1) != line_of(k) ? 1 : 0;
}

}  // namespace mirage::sensor
