// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/polygon.hpp"

#include <cmath>
#include <numbers>

#include "mirage/core/error.hpp"

namespace mirage::sensor {

PolygonPattern::PolygonPattern(AirborneConfig config) : AirbornePattern(config) {
    if (config_.kind != AirborneKind::Polygon)
        throw ConfigError("sensor: airborne: polygon pattern needs pattern polygon");
}

void PolygonPattern::steer(std::uint64_t k, PulseSpec& p) const {
    const double x = lines(k);
    const double line = std::floor(x);
    const double theta_deg = config_.fov_deg * (x - line - 0.5);
    const double th = theta_deg * std::numbers::pi / 180.0;
    p.dir =
        Eigen::Vector3f(0.0f, static_cast<float>(-std::sin(th)), static_cast<float>(-std::cos(th)));
    p.scan_angle_deg = static_cast<float>(theta_deg);
    p.scan_direction = 1;
    p.edge_of_flight_line = std::floor(lines(k + 1)) != line ? 1 : 0;
}

double PolygonPattern::lines(std::uint64_t k) const {
    return static_cast<double>(k) * (config_.scan_rate_hz * config_.facets) / config_.prf_hz;
}

}  // namespace mirage::sensor
