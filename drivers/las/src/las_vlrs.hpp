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
// With `events`, the photon-event fields follow (or stand alone): "pixel" (u32), "event" (u8:
// 1 signal, 2 background or dark, 3 afterpulse, 4 crosstalk, 0 none) and "time of flight" (f64,
// ns since emission).
std::vector<std::uint8_t> extra_bytes_vlr(bool echo, bool events);
inline constexpr std::size_t kEchoExtraBytes = 12;
inline constexpr std::size_t kEventExtraBytes = 13;

}  // namespace mirage::las
