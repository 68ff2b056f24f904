// SPDX-License-Identifier: Apache-2.0
// One pulse seen by the waveform detector, for tests and previews: the pipeline's own rays,
// trace and arrival building (docs/time-resolved.md §2), without detection.
#pragma once
#include <cstdint>
#include <vector>

#include "mirage/physics/waveform.hpp"
#include "mirage/render/setup.hpp"

namespace mirage::render {

// Pulse `pulse`'s arrivals sorted by delay: one per sub-ray hit within the receiver's ranges and
// one per hit of its paths beyond the first (time-resolved.md §5), with its expected
// photo-electrons (whatever detector the sensor has). Arrival::hit below the pulse's sub-ray
// count is a sub-ray's own hit.
std::vector<physics::Arrival> pulse_arrivals(const Setup& setup, std::uint64_t pulse);

}  // namespace mirage::render
