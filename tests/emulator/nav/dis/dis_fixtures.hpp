// SPDX-License-Identifier: Apache-2.0
// An entity in motion with every dead-reckoning term set, for the DIS tests.
#pragma once
#include <cstdint>

#include "mirage/dis/entity_state.hpp"

namespace mirage::dis {

inline EntityState moving(std::uint8_t algorithm) {
    EntityState s;
    s.location = {6'378'137.0, 0, 0};
    s.psi = 0.4f;
    s.theta = -1.2f;
    s.phi = 0.1f;
    s.velocity = {3.0f, -4.0f, 12.0f};
    s.dr_acceleration = {0.5f, -0.25f, 1.0f};
    s.dr_angular_velocity = {0.05f, -0.1f, 0.5f};
    s.dr_algorithm = algorithm;
    return s;
}

}  // namespace mirage::dis
