// SPDX-License-Identifier: Apache-2.0
// libFuzzer: Ouster metadata JSON (all three shapes) into a descriptor. Bad input must end in
// ConfigError; an accepted descriptor must build a decoder and survive its own round trip.
#include <cstddef>
#include <cstdint>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/ouster/decoder.hpp"
#include "mirage/ouster/metadata.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace mirage::ouster;
    const std::string text(reinterpret_cast<const char*>(data), size);
    Descriptor d;
    try {
        d = descriptor_from_metadata(text, "fuzz");
    } catch (const mirage::ConfigError&) {
        return 0;
    }
    if (d.altitude_deg.size() != d.beams || d.azimuth_deg.size() != d.beams) __builtin_trap();
    const Decoder dec(d);
    try {
        const Descriptor again = descriptor_from_metadata(metadata_json(d), "round trip");
        if (again.beams != d.beams || again.profile != d.profile || !(again.mode == d.mode))
            __builtin_trap();
    } catch (const mirage::ConfigError&) {
        __builtin_trap();
    }
    return 0;
}
