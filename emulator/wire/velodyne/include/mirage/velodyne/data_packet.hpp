// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <span>

#include "mirage/velodyne/model.hpp"

namespace mirage::velodyne {

// docs/wire-formats.md §1.2: 12 blocks × (flag, azimuth, 32 × (distance, reflectivity)), timestamp,
// two factory bytes. Little-endian.
inline constexpr std::size_t kDataPacketSize = 1206;
inline constexpr int kBlocksPerPacket = 12;
inline constexpr int kSlotsPerBlock = 32;
inline constexpr std::size_t kBlockSize = 100;
inline constexpr std::size_t kTimestampOffset = 1200;
inline constexpr std::size_t kFactoryOffset = 1204;
inline constexpr std::uint16_t kUpperBlockFlag = 0xEEFF;
inline constexpr std::uint16_t kLowerBlockFlag = 0xDDFF;
inline constexpr std::uint16_t kAzimuthCounts = 36'000;  // 0.01° units, 0..35999

// Field-level content of a data packet (no interpretation: what the bytes say).
struct RawChannel {
    std::uint16_t distance = 0;  // LSB per model; 0 = no return
    std::uint8_t reflectivity = 0;
};
struct RawBlock {
    std::uint16_t flag = kUpperBlockFlag;
    std::uint16_t azimuth = 0;
    std::array<RawChannel, kSlotsPerBlock> channel{};
};
struct RawDataPacket {
    std::array<RawBlock, kBlocksPerPacket> block{};
    std::uint32_t timestamp_us = 0;
    std::uint8_t factory1 = 0;  // return mode (HDL-64E: status type)
    std::uint8_t factory2 = 0;  // product id (HDL-64E: status value)
};

// Writes exactly kDataPacketSize bytes.
void encode_data(const RawDataPacket& p, std::span<std::uint8_t, kDataPacketSize> out);
// Reads the fields of a buffer of exactly kDataPacketSize bytes (no checks).
RawDataPacket parse_data(std::span<const std::uint8_t, kDataPacketSize> in);

// Decoder outcome, checked in this order: length, block flags, ids, fields.
enum class DecodeStatus : std::uint8_t {
    Ok,
    WrongSize,        // payload not 1206 bytes
    BadBlockFlag,     // a flag other than the model's 0xEEFF / 0xDDFF pattern
    UnknownProduct,   // byte 1205 is no supported product (auto-detection)
    ProductMismatch,  // a supported product, not the expected model
    BadReturnMode,    // byte 1204 not 0x37/0x38/0x39
    BadAzimuth,       // an azimuth ≥ 36000, or dual pairs with different azimuths
    BadTimestamp,     // ≥ 3 600 000 000 µs
};
inline constexpr std::size_t kDecodeStatusCount = 8;
const char* to_string(DecodeStatus s);

// Counts every decoder outcome.
struct DecodeCounters {
    std::array<std::uint64_t, kDecodeStatusCount> count{};
    void add(DecodeStatus s) { ++count[static_cast<std::size_t>(s)]; }
    std::uint64_t operator[](DecodeStatus s) const { return count[static_cast<std::size_t>(s)]; }
    std::uint64_t total() const;
    std::uint64_t errors() const { return total() - (*this)[DecodeStatus::Ok]; }
};

// One decoded slot. Azimuth is the beam's (rotor azimuth interpolated to the firing time plus the
// laser's offset δ), clockwise from +x, [0, 360). xyz in the sensor frame, FLU, the same
// convention as SpinningPattern: (d·cos el·cos az, −d·cos el·sin az, d·sin el); zeros when d = 0.
struct Firing {
    float azimuth_deg = 0;
    float distance_m = 0;  // 0 = no return
    float x = 0, y = 0, z = 0;
    std::int32_t time_offset_ns = 0;  // after the packet timestamp (first firing)
    std::uint16_t raw_distance = 0;
    std::uint8_t reflectivity = 0;
    std::uint8_t laser = 0;
    std::uint8_t ret = 0;       // 0 single / dual last, 1 dual strongest or second strongest
    std::uint8_t sequence = 0;  // firing sequence within the packet
};

struct DecodedPacket {
    const ModelDescriptor* model = nullptr;
    ReturnMode mode = ReturnMode::Strongest;
    std::uint32_t timestamp_us = 0;
    std::uint8_t factory1 = 0, factory2 = 0;
    std::array<std::uint16_t, kBlocksPerPacket> block_azimuth{};
    // Block b, slot c at [32·b + c].
    std::array<Firing, kBlocksPerPacket * kSlotsPerBlock> firing{};
};

// Decodes a data packet. `expected` null: the model comes from byte 1205 (HDL-64E from its block
// flags); otherwise the packet must be that model. HDL-64E has no return-mode byte: dual is
// recognised by blocks 0 and 2 sharing an azimuth (VeloView's rule). Never throws, never reads
// outside `bytes`; `out` is complete only when the result is Ok.
DecodeStatus decode_data(std::span<const std::uint8_t> bytes, const ModelDescriptor* expected,
                         DecodedPacket& out);

}  // namespace mirage::velodyne
