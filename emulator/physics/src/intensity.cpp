// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cmath>

#include "mirage/core/log_poly.hpp"
#include "mirage/physics/radiometry.hpp"

namespace mirage::physics {

std::uint16_t IntensityCalibration::to_u16(double n_laser) const {
    return to_u16(n_laser, log_range());
}

void IntensityCalibration::to_u16_many(const double* n_laser, std::size_t count,
                                       std::uint16_t* out) const {
    if (!(n_min > 0.0) || !(n_max > n_min)) {  // the step map: no logarithm
        for (std::size_t j = 0; j < count; ++j) out[j] = to_u16(n_laser[j]);
        return;
    }
    const double log_range_v = log_range();
    for (std::size_t j = 0; j < count; ++j) {
        const double n = n_laser[j];
        // log_poly is unspecified outside the positive normals: those values are selected away.
        const double f = std::clamp(core::log_poly(n / n_min) / log_range_v, 0.0, 1.0);
        const double above_min = n > n_min ? f : 0.0;  // also 0, negative and NaN
        const double frac = n >= n_max ? 1.0 : above_min;
        out[j] = static_cast<std::uint16_t>(frac * 65535.0 + 0.5);
    }
}

std::uint8_t IntensityCalibration::to_u8(double n_laser) const {
    return static_cast<std::uint8_t>(std::lround(fraction(n_laser, log_range()) * 255.0));
}

}  // namespace mirage::physics
