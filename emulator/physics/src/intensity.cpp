// SPDX-License-Identifier: Apache-2.0
#include <cmath>

#include "mirage/physics/radiometry.hpp"

namespace mirage::physics {

std::uint16_t IntensityCalibration::to_u16(double n_laser) const {
    return to_u16(n_laser, log_range());
}

std::uint8_t IntensityCalibration::to_u8(double n_laser) const {
    return static_cast<std::uint8_t>(std::lround(fraction(n_laser, log_range()) * 255.0));
}

}  // namespace mirage::physics
