// SPDX-License-Identifier: Apache-2.0
// libFuzzer: arbitrary bulk-IN packets into the gs_host_frame validator, plus arbitrary BT_CONST
// limits into the bit-timing search. Neither may read out of bounds or yield an invalid result.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "gsusb_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace mirage::can::gsusb;
    const DecodedHostFrame d = decode_host_frame(data, size, size > 0 ? data[0] & 1 : 0);
    if (d.kind != HostFrameKind::Malformed && d.frame.len > 8) std::abort();
    if (size >= kBtConstSize + 4) {
        const BtConst c = parse_bt_const(data);
        const auto bt = compute_bit_timing(c, get_u32(data + kBtConstSize));
        if (bt && (bt->brp == 0 || bt->sjw == 0)) std::abort();
    }
    return 0;
}
