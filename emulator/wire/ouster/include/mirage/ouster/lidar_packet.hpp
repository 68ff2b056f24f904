// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "mirage/ouster/descriptor.hpp"

namespace mirage::ouster {

// CRC-64/XZ (§2.5): reflected ECMA-182, init and xorout all ones. "123456789" → 0x995DC9BBDF1939FA.
std::uint64_t crc64_xz(std::span<const std::uint8_t> bytes);

// Non-legacy packet header (§2.4, STANDARD type); LEGACY packets have none (frame ID per column).
struct PacketHeader {
    std::uint16_t packet_type = kPacketTypeLidar;
    std::uint16_t frame_id = 0;
    std::uint32_t init_id = 0;  // 24 bits
    std::uint64_t serial = 0;   // 40 bits
    std::uint8_t alert_flags = 0;
    std::uint8_t thermal_shutdown_countdown = 0;
    std::uint8_t shot_limiting_countdown = 0;
    std::uint8_t thermal_shutdown_status = 0;  // low nibble
    std::uint8_t shot_limiting_status = 0;     // low nibble
};

struct ColumnHeader {
    std::uint64_t timestamp_ns = 0;
    std::uint16_t measurement_id = 0;
    std::uint16_t frame_id = 0;       // LEGACY only (non-legacy: header frame ID)
    std::uint32_t encoder_count = 0;  // LEGACY only
    std::uint32_t status = 0;         // LEGACY 0xFFFFFFFF / 0; non-legacy u16, bit 0 = valid
    bool valid() const { return (status & 1u) != 0; }
};

// One pixel in decoded units: range in mm (0 = no return), NIR in photons.
struct Pixel {
    std::uint32_t range_mm = 0;
    std::uint8_t flags = 0;
    std::uint16_t reflectivity = 0;
    std::uint16_t signal = 0;
    std::uint16_t nir = 0;
};

// A lidar packet in memory: columns_per_packet columns, pixels column-major (column c, row r at
// c·H + r).
struct LidarPacket {
    PacketHeader header;
    std::vector<ColumnHeader> columns;
    std::vector<Pixel> pixels;
    std::uint64_t footer_word = 0;  // last 8 bytes of a non-legacy packet, as read
    void resize(const Descriptor& d);
    Pixel& pixel(std::size_t column, std::size_t row, std::size_t beams) {
        return pixels[column * beams + row];
    }
    const Pixel& pixel(std::size_t column, std::size_t row, std::size_t beams) const {
        return pixels[column * beams + row];
    }
};

// Column status word the encoder writes for a valid / dropped column.
std::uint32_t valid_column_status(const Descriptor& d);

// Writes `p` into `out`, which must hold exactly d.packet_bytes() (else returns false and writes
// nothing). Values wider than their field saturate (range) or are masked (flags); RNG15 ranges
// round to 8 mm and NIR to 16. The footer follows d.footer.
bool encode_lidar_packet(const Descriptor& d, const LidarPacket& p, std::span<std::uint8_t> out);

// Checks in this fixed order, stopping at the first failure: length; packet type (non-legacy);
// init ID / serial (non-legacy, when non-zero they must equal the descriptor's); footer (CRC-64
// unless it is the FW 2.x placeholder); per column: status word, measurement ID (< W and
// consecutive within the packet), LEGACY frame ID (same in every column) and encoder count.
// Dropped columns (status bit 0 clear) skip the field checks. Never throws, never reads outside
// `bytes`; `out` is filled as far as decoding got.
enum class DecodeStatus : std::uint8_t {
    Ok,
    WrongSize,
    BadPacketType,
    BadInitId,
    BadSerial,
    BadCrc,
    BadColumnStatus,
    BadMeasurementId,
    BadFrameId,
    BadEncoderCount,
};
inline constexpr std::size_t kDecodeStatusCount = 10;
const char* to_string(DecodeStatus s);

// What the footer held (non-legacy packets; None for LEGACY).
enum class FooterCheck : std::uint8_t { None, CrcValid, Placeholder, CrcInvalid };

DecodeStatus decode_lidar_packet(const Descriptor& d, std::span<const std::uint8_t> bytes,
                                 LidarPacket& out, FooterCheck* footer = nullptr);

}  // namespace mirage::ouster
