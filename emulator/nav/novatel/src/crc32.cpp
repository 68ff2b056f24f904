// SPDX-License-Identifier: Apache-2.0
#include "mirage/novatel/crc32.hpp"

#include <array>

namespace mirage::novatel {
namespace {

// Byte-wise table of the reflected polynomial (§2.2 pseudo-code, precomputed per byte value).
constexpr std::array<std::uint32_t, 256> make_table() {
    std::array<std::uint32_t, 256> table{};
    for (std::uint32_t i = 0; i < 256; ++i) {
        std::uint32_t t = i;
        for (int k = 0; k < 8; ++k) t = (t & 1U) ? (t >> 1) ^ 0xEDB88320U : t >> 1;
        table[i] = t;
    }
    return table;
}
constexpr std::array<std::uint32_t, 256> kTable = make_table();

}  // namespace

std::uint32_t crc32_update(std::uint32_t crc, std::span<const std::uint8_t> bytes) {
    for (std::uint8_t b : bytes) crc = (crc >> 8) ^ kTable[(crc ^ b) & 0xFFU];
    return crc;
}

std::uint32_t crc32(std::span<const std::uint8_t> bytes) { return crc32_update(0, bytes); }

}  // namespace mirage::novatel
