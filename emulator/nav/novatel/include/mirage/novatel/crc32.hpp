// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <span>

namespace mirage::novatel {

// NovAtel's CRC-32 (docs/nav-protocols.md §2.2): reflected polynomial 0xEDB88320, initial value 0,
// no final XOR. Check value of "123456789" is 0x2DFD2D88 (not zlib's CRC-32).
std::uint32_t crc32(std::span<const std::uint8_t> bytes);
// Continues a CRC over more bytes: crc32(a ++ b) == crc32_update(crc32(a), b).
std::uint32_t crc32_update(std::uint32_t crc, std::span<const std::uint8_t> bytes);

}  // namespace mirage::novatel
