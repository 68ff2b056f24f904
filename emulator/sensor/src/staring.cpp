// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/staring.hpp"

#include <algorithm>
#include <cmath>

#include "mirage/core/error.hpp"
#include "scan_math.hpp"

namespace mirage::sensor {

StaringPattern::StaringPattern(double prf_hz, bool nadir)
    : prf_hz_(prf_hz), period_ns_(1e9 / prf_hz), nadir_(nadir) {
    if (!(prf_hz > 0) || prf_hz > 1e9)
        throw ConfigError("sensor: staring: prf must be in (0, 1 GHz]");
}

std::uint64_t StaringPattern::pulse_count(core::Nanos duration) const {
    return detail::fixed_rate_count(duration.count(), period_ns_);
}

void StaringPattern::pulses(std::uint64_t first, std::size_t n, PulseSpec* out) const {
    for (std::size_t i = 0; i < n; ++i) {
        PulseSpec& p = out[i];
        p = PulseSpec{};
        p.t_ns = detail::fixed_rate_time_ns(first + i, period_ns_);
        p.dir = nadir_ ? Eigen::Vector3f(0, 0, -1) : Eigen::Vector3f(1, 0, 0);
    }
}

}  // namespace mirage::sensor
