// SPDX-License-Identifier: Apache-2.0
// libFuzzer: the OxTS and SBG CAN decoders on arbitrary frames. Byte 0 picks the decoder (bit 0)
// and 29-bit identifiers (bit 1, as the units can be set to send); the rest is 14-byte records
// (fuzz_can_record.hpp): the decoders see any ID, DLC, data and spacing in time.
#include <cstddef>
#include <cstdint>
#include <numbers>

#include "fuzz_can_record.hpp"
#include "mirage/navcan/oxts_can.hpp"
#include "mirage/navcan/sbg_can.hpp"

using namespace mirage;

namespace {

void check(const nav::NavSample& s) {
    if (s.has(nav::NavSample::kAttitude) &&
        !(s.heading_rad >= 0.0 && s.heading_rad < 2 * std::numbers::pi))
        __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const bool oxts = (data[0] & 1) == 0;
    const bool extended = (data[0] & 2) != 0;
    navcan::OxtsCanConfig oc;
    oc.ids.extended = extended;
    navcan::OxtsCanDecoder ox(oc);
    navcan::SbgCanIds sc;
    sc.extended = extended;
    navcan::SbgCanDecoder sbg(sc);
    navcan::test::for_each_record({data + 1, size - 1}, [&](const nav::StampedCanFrame& f) {
        if (oxts)
            ox.feed(f, check);
        else
            sbg.feed(f.frame, check);
    });
    ox.flush(check);
    sbg.flush(check);
    return 0;
}
