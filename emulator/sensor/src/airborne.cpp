// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/airborne.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "mirage/core/error.hpp"
#include "mirage/core/rounding.hpp"
#include "mirage/sensor/oscillating_mirror.hpp"
#include "mirage/sensor/palmer.hpp"
#include "mirage/sensor/polygon.hpp"
#include "scan_math.hpp"

namespace mirage::sensor {

std::string to_string(AirborneKind kind) {
    switch (kind) {
        case AirborneKind::Sawtooth:
            return "sawtooth";
        case AirborneKind::Sine:
            return "sine";
        case AirborneKind::Polygon:
            return "polygon";
        case AirborneKind::Palmer:
            return "palmer";
    }
    return "?";
}

double AirborneConfig::lines_per_s() const {
    switch (kind) {
        case AirborneKind::Sawtooth:
        case AirborneKind::Sine:
        case AirborneKind::Palmer:
            return 2.0 * scan_rate_hz;
        case AirborneKind::Polygon:
            return scan_rate_hz * facets;
    }
    return scan_rate_hz;
}

AirbornePattern::AirbornePattern(AirborneConfig config) : config_(config) {
    const auto fail = [](const std::string& what) {
        throw ConfigError("sensor: airborne: " + what);
    };
    if (!(config_.prf_hz > 0) || config_.prf_hz > 1e9) fail("prf must be in (0, 1 GHz]");
    if (!(config_.scan_rate_hz > 0) || !std::isfinite(config_.scan_rate_hz))
        fail("scan rate must be positive");
    if (!(config_.fov_deg > 0 && config_.fov_deg < 180)) fail("fov must be in (0°, 180°)");
    if (config_.facets < 1) fail("facets must be at least 1");
    if (!(std::abs(config_.tilt_deg) <= 60)) fail("tilt must be within ±60°");
    period_ns_ = 1e9 / config_.prf_hz;
    const double tilt = config_.tilt_deg * std::numbers::pi / 180.0;
    cos_tilt_ = std::cos(tilt);
    sin_tilt_ = std::sin(tilt);
}

double AirbornePattern::cycles(std::uint64_t k) const {
    // Multiply before dividing: k·rate is exact for integer rates, so line boundaries land on
    // whole pulses when prf/lines is an integer.
    return static_cast<double>(k) * config_.scan_rate_hz / config_.prf_hz;
}

std::int64_t AirbornePattern::time_ns(std::uint64_t k) const {
    return detail::fixed_rate_time_ns(k, period_ns_);
}

std::uint64_t AirbornePattern::pulse_count(core::Nanos duration) const {
    return detail::fixed_rate_count(duration.count(), period_ns_);
}

void AirbornePattern::pulses(std::uint64_t first, std::size_t n, PulseSpec* out) const {
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint64_t k = first + i;
        PulseSpec& p = out[i];
        p = PulseSpec{};
        p.t_ns = time_ns(k);
        p.channel = 0;
        steer(k, p);
        if (config_.tilt_deg != 0) {
            // Pitch forward about +y: nadir (0, 0, −1) → (sin t, 0, −cos t).
            const float x = p.dir.x(), z = p.dir.z();
            p.dir.x() = static_cast<float>(cos_tilt_ * x - sin_tilt_ * z);
            p.dir.z() = static_cast<float>(sin_tilt_ * x + cos_tilt_ * z);
        }
        // A beam in the y-z plane (no tilt) points at ±90°: the value atan2 gives (π/2 is
        // correctly rounded), without the library call.
        const double y = -double(p.dir.y()), x = double(p.dir.x());
        const double rad =
            x == 0.0 && y != 0.0 ? std::copysign(std::numbers::pi / 2, y) : std::atan2(y, x);
        const double az = rad * 180.0 / std::numbers::pi;
        p.azimuth_deg = static_cast<float>(detail::wrap_deg(az));
        if (p.azimuth_deg >= 360.0f) p.azimuth_deg = 0.0f;
    }
}

std::shared_ptr<const AirbornePattern> make_airborne_pattern(const AirborneConfig& config) {
    switch (config.kind) {
        case AirborneKind::Sawtooth:
        case AirborneKind::Sine:
            return std::make_shared<OscillatingMirrorPattern>(config);
        case AirborneKind::Polygon:
            return std::make_shared<PolygonPattern>(config);
        case AirborneKind::Palmer:
            return std::make_shared<PalmerPattern>(config);
    }
    throw ConfigError("sensor: airborne: unknown pattern");
}

}  // namespace mirage::sensor
