// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace mirage::novatel {

inline constexpr std::uint8_t kSync0 = 0xAA;
inline constexpr std::uint8_t kSync1 = 0x44;
inline constexpr std::uint8_t kSyncLong = 0x12;
inline constexpr std::uint8_t kSyncShort = 0x13;
inline constexpr std::size_t kLongHeaderSize = 28;
inline constexpr std::size_t kShortHeaderSize = 12;
inline constexpr std::size_t kCrcSize = 4;
// Longest body the decoder waits for; a longer announced length is a false sync (§2.1 has
// u16 lengths, the logs we read are < 200 bytes).
inline constexpr std::size_t kMaxBodyLength = 4096;

// Long (28-byte) header, docs/nav-protocols.md §2.1. body_length is filled by frame_long().
struct LongHeader {
    std::uint8_t header_length = static_cast<std::uint8_t>(kLongHeaderSize);
    std::uint16_t message_id = 0;
    std::uint8_t message_type = 0;     // bits 5-6 format (00 binary), bit 7 response
    std::uint8_t port_address = 0x20;  // COM1
    std::uint16_t body_length = 0;
    std::uint16_t sequence = 0;
    std::uint8_t idle_time = 0;
    std::uint8_t time_status = 180;  // FINESTEERING
    std::uint16_t week = 0;
    std::uint32_t ms_of_week = 0;
    std::uint32_t receiver_status = 0;
    std::uint16_t reserved = 0;
    std::uint16_t software_build = 0;
};

// Short (12-byte) header used by the "…S" logs.
struct ShortHeader {
    std::uint8_t body_length = 0;
    std::uint16_t message_id = 0;
    std::uint16_t week = 0;
    std::uint32_t ms_of_week = 0;
};

// Time status values (OEM7 "GPS reference time status"); below kTimeApproximate the header time
// is not a GPS time.
inline constexpr std::uint8_t kTimeUnknown = 20;
inline constexpr std::uint8_t kTimeApproximate = 60;
inline constexpr std::uint8_t kTimeFineSteering = 180;

// A whole frame: header + body + CRC-32 (little-endian), CRC over everything before it.
std::vector<std::uint8_t> frame_long(LongHeader header, std::span<const std::uint8_t> body);
std::vector<std::uint8_t> frame_short(ShortHeader header, std::span<const std::uint8_t> body);

// Header parsers for a complete, CRC-checked frame (nullopt if the bytes are not one).
std::optional<LongHeader> parse_long_header(std::span<const std::uint8_t> frame);
std::optional<ShortHeader> parse_short_header(std::span<const std::uint8_t> frame);

}  // namespace mirage::novatel
