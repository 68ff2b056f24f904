// SPDX-License-Identifier: Apache-2.0
#pragma once
// The descriptors fuzz_ouster_decode picks from with byte 0 (shared with the seed generator):
// each profile × 32/64/128 beams × 16/8 columns per packet; the 8-column kinds end in the FW 2.x
// placeholder footer, the others in a CRC-64.
#include <vector>

#include "mirage/ouster/descriptor.hpp"

namespace mirage::ouster::test {

inline const std::vector<Descriptor>& fuzz_kinds() {
    static const std::vector<Descriptor> all = [] {
        std::vector<Descriptor> v;
        for (Profile p : {Profile::Legacy, Profile::Rng19Rfl8Sig16Nir16, Profile::Rng15Rfl8Nir8})
            for (int beams : {32, 64, 128})
                for (int cols : {16, 8}) {
                    v.push_back(make_descriptor(ProductLine::OS1, beams, {512, 10}, p, cols));
                    if (cols == 8) v.back().footer = FooterKind::Fw2Placeholder;
                }
        return v;
    }();
    return all;
}

}  // namespace mirage::ouster::test
