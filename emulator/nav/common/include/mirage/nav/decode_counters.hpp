// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

namespace mirage::nav {

// What a stream decoder saw, counted, never thrown: bytes from outside are validated in one
// place in a fixed order (length, sync/magic, ids, checksum, fields).
struct DecodeCounters {
    std::uint64_t messages_ok = 0;      // complete, valid messages decoded
    std::uint64_t samples = 0;          // NavSamples delivered
    std::uint64_t garbage_bytes = 0;    // bytes skipped while resynchronising
    std::uint64_t truncated = 0;        // a message cut short (next sync arrived first, or too long)
    std::uint64_t bad_checksum = 0;     // checksum or CRC mismatch
    std::uint64_t unsupported = 0;      // valid framing, a message type we do not decode
    std::uint64_t invalid_field = 0;    // NaN/Inf, out-of-range or malformed field values

    std::uint64_t rejected() const { return truncated + bad_checksum + invalid_field; }
};

}  // namespace mirage::nav
