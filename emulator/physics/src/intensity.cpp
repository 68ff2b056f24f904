// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cmath>

#include "mirage/physics/radiometry.hpp"

namespace mirage::physics {
namespace {

// Fraction in [0, 1] of the log-scaled calibration range.
double calibrated_fraction(double n, double n_min, double n_max) {
    if (!(n_min > 0.0) || !(n_max > n_min)) return n >= n_max ? 1.0 : 0.0;
    if (!(n > n_min)) return 0.0;  // also 0, negative and NaN
    if (n >= n_max) return 1.0;
    return std::clamp(std::log(n / n_min) / std::log(n_max / n_min), 0.0, 1.0);
}

}  // namespace

std::uint16_t IntensityCalibration::to_u16(double n_laser) const {
    const double f = calibrated_fraction(n_laser, n_min, n_max);
    return static_cast<std::uint16_t>(std::lround(f * 65535.0));
}

std::uint8_t IntensityCalibration::to_u8(double n_laser) const {
    const double f = calibrated_fraction(n_laser, n_min, n_max);
    return static_cast<std::uint8_t>(std::lround(f * 255.0));
}

}  // namespace mirage::physics
