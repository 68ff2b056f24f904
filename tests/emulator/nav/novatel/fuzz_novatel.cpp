// SPDX-License-Identifier: Apache-2.0
// libFuzzer target (Clang): the stream decoder must count, never crash or read out of bounds,
// for any bytes and any split of them.
#include <cstddef>
#include <cstdint>
#include <span>

#include "mirage/novatel/decoder.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> bytes(data, size);
    std::uint64_t seen = 0;
    const auto on_sample = [&seen](const mirage::nav::NavSample&) { ++seen; };

    mirage::novatel::NovatelDecoder whole;
    whole.feed(bytes, on_sample);
    whole.finish();

    // Same bytes in pieces whose sizes come from the data itself: counters must not depend on
    // the split.
    mirage::novatel::NovatelDecoder split;
    std::size_t off = 0;
    std::size_t step = size > 0 ? (data[0] % 17) + 1 : 1;
    while (off < size) {
        const std::size_t n = step < size - off ? step : size - off;
        split.feed(bytes.subspan(off, n), on_sample);
        off += n;
        step = (step * 7 + 3) % 23 + 1;
    }
    split.finish();
    const auto& a = whole.counters();
    const auto& b = split.counters();
    if (a.messages_ok != b.messages_ok || a.garbage_bytes != b.garbage_bytes ||
        a.bad_checksum != b.bad_checksum || a.unsupported != b.unsupported ||
        a.invalid_field != b.invalid_field)
        __builtin_trap();
    return 0;
}
