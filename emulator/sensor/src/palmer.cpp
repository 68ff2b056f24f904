// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/palmer.hpp"

#include <cmath>
#include <numbers>

#include "mirage/core/error.hpp"

namespace mirage::sensor {

PalmerPattern::PalmerPattern(AirborneConfig config) : AirbornePattern(config) {
    if (config_.kind != AirborneKind::Palmer)
        throw ConfigError("sensor: airborne: Palmer pattern needs pattern palmer");
}

void PalmerPattern::steer(std::uint64_t k, PulseSpec& p) const {
    const double x = cycles(k);
    const double phi = 2.0 * std::numbers::pi * x;
    const double c = 0.5 * config_.fov_deg * std::numbers::pi / 180.0;
    const double right = std::sin(c) * std::sin(phi);
    p.dir = Eigen::Vector3f(static_cast<float>(std::sin(c) * std::cos(phi)),
                            static_cast<float>(-right), static_cast<float>(-std::cos(c)));
    p.scan_angle_deg =
        static_cast<float>(std::atan2(right, std::cos(c)) * 180.0 / std::numbers::pi);
    // Moving right while the beam is in the forward half (d sin φ / dφ = cos φ > 0).
    p.scan_direction = std::cos(phi) > 0 ? 1 : 0;
    p.edge_of_flight_line =
        std::floor(2.0 * cycles(k + 1) + 0.5) != std::floor(2.0 * x + 0.5) ? 1 : 0;
}

}  // namespace mirage::sensor
