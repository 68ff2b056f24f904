// SPDX-License-Identifier: Apache-2.0
#include "mirage/novatel/crc32.hpp"

#include <lzma.h>

namespace mirage::novatel {

// NovAtel's CRC is the common reflected CRC-32 without its initial and final inversion; liblzma's
// lzma_crc32 inverts on the way in and out, so inverting around it gives NovAtel's register.
std::uint32_t crc32_update(std::uint32_t crc, std::span<const std::uint8_t> bytes) {
    return ~lzma_crc32(bytes.data(), bytes.size(), ~crc);
}

std::uint32_t crc32(std::span<const std::uint8_t> bytes) { return crc32_update(0, bytes); }

}  // namespace mirage::novatel
