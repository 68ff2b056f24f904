// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>

#include "mirage/ouster/descriptor.hpp"
#include "mirage/ouster/sensor_clock.hpp"

namespace mirage::ouster {

// The JSON shapes of docs/wire-formats.md §2.7.
enum class MetadataShape : std::uint8_t {
    Nested,  // FW ≥ 2.4 / 3.x: sensor_info, beam_intrinsics, lidar_data_format, config_params …
    Fw2Flat,  // FW 2.x flat: the key set of os2_128_rng19.json
};

struct MetadataOptions {
    MetadataShape shape = MetadataShape::Nested;
    TimestampMode timestamp_mode = TimestampMode::InternalOsc;
    std::string udp_dest = "127.0.0.1";
};

// The sensor metadata ouster-sdk's SensorInfo reads, from the same descriptor the packets use
// (serial and init ID identical to the packet headers). Pure function; numbers are written as
// shortest round-trip decimals.
std::string metadata_json(const Descriptor& d, const MetadataOptions& options = {});

// Reads any of the three shapes (FW 1.x flat: angles + lidar_mode only, everything else from the
// §2.7 defaults and LEGACY) into a descriptor. `source` names the input in errors:
// ConfigError "ouster metadata '<source>': <key>: <problem>".
Descriptor descriptor_from_metadata(const std::string& json, const std::string& source);
// Same, reading a file (IoError when it cannot be read).
Descriptor load_metadata(const std::string& path);

}  // namespace mirage::ouster
