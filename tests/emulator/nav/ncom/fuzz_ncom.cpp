// SPDX-License-Identifier: Apache-2.0
// libFuzzer target (Clang): the NCOM stream and datagram decoders must count, never crash or
// read out of bounds; stream counters must not depend on the split.
#include <cstddef>
#include <cstdint>
#include <span>

#include "mirage/ncom/decoder.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> bytes(data, size);
    const auto on_sample = [](const mirage::nav::NavSample& s) {
        // Decoded samples obey the NavSample conventions.
        if (s.heading_rad < 0.0 || s.heading_rad >= 6.283185307179587) __builtin_trap();
        if (s.lat_deg < -90.0 || s.lat_deg > 90.0) __builtin_trap();
    };

    mirage::ncom::NcomDecoder whole;
    whole.feed(bytes, on_sample);
    whole.finish();

    mirage::ncom::NcomDecoder split;
    std::size_t off = 0;
    std::size_t step = size > 0 ? (data[0] % 13) + 1 : 1;
    while (off < size) {
        const std::size_t n = step < size - off ? step : size - off;
        split.feed(bytes.subspan(off, n), on_sample);
        off += n;
        step = (step * 5 + 1) % 97 + 1;
    }
    split.finish();
    const auto& a = whole.counters();
    const auto& b = split.counters();
    if (a.messages_ok != b.messages_ok || a.garbage_bytes != b.garbage_bytes ||
        a.bad_checksum != b.bad_checksum || a.samples != b.samples)
        __builtin_trap();

    mirage::ncom::NcomDecoder datagram;
    datagram.feed_datagram(bytes, on_sample);
    return 0;
}
