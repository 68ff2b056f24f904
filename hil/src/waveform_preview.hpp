// SPDX-License-Identifier: Apache-2.0
// A PNG of chosen pulses' recorded waveforms with their returns marked (`mirage las-info
// --waveform-png`, `mirage demo`).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mirage/las/las_reader.hpp"

namespace mirage::hil {

// One panel per point of `asked` (empty: the first four packets with the most returns), each
// return sharing the packet marked; prints one line per panel. ConfigError for a point that is
// not in the file or has no valid packet, or when there is nothing to draw.
void write_waveform_preview(const std::string& png, const las::LasFile& f,
                            const std::vector<std::uint64_t>& asked);

}  // namespace mirage::hil
