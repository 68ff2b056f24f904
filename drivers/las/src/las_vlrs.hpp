// SPDX-License-Identifier: Apache-2.0
// The variable length records the LAS writer adds (LAS 1.4 §2.5, §4; docs/file-formats.md §6): each
// as its bytes, 54-byte header included.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mirage/las/las_writer.hpp"

namespace mirage::las {

// OGC WKT coordinate system (LASF_Projection 2112). ConfigError if too long for a VLR.
std::vector<std::uint8_t> wkt_vlr(const std::string& wkt, const std::string& prefix);
// Waveform packet descriptor index 1 (LASF_Spec 100).
std::vector<std::uint8_t> waveform_descriptor_vlr(const WaveformPackets& w);
// Extra bytes (LASF_Spec 4): the waveform detector's amplitude, echo width and deviation, one
// float each, in that order after the format's own fields.
std::vector<std::uint8_t> echo_extra_bytes_vlr();
inline constexpr std::size_t kEchoExtraBytes = 12;

}  // namespace mirage::las
