// SPDX-License-Identifier: Apache-2.0
// Byte layout of LAS 1.4 (ASPRS LAS Specification 1.4 R15, §2.4 header, §2.5 VLR, §2.6
// point data record formats) and little-endian accessors shared by the writer and reader.
#pragma once
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace mirage::las::layout {

// Public header block field offsets (Table 3).
inline constexpr std::size_t kSignature = 0;
inline constexpr std::size_t kFileSourceId = 4;
inline constexpr std::size_t kGlobalEncoding = 6;
inline constexpr std::size_t kVersionMajor = 24;
inline constexpr std::size_t kVersionMinor = 25;
inline constexpr std::size_t kSystemIdentifier = 26;
inline constexpr std::size_t kGeneratingSoftware = 58;
inline constexpr std::size_t kCreationDay = 90;
inline constexpr std::size_t kCreationYear = 92;
inline constexpr std::size_t kHeaderSize = 94;
inline constexpr std::size_t kOffsetToPoints = 96;
inline constexpr std::size_t kVlrCount = 100;
inline constexpr std::size_t kPointFormat = 104;
inline constexpr std::size_t kRecordLength = 105;
inline constexpr std::size_t kLegacyPointCount = 107;
inline constexpr std::size_t kLegacyByReturn = 111;  // u32[5]
inline constexpr std::size_t kScale = 131;           // f64[3]
inline constexpr std::size_t kOffset = 155;          // f64[3]
inline constexpr std::size_t kMaxX = 179;            // max x, min x, max y, min y, max z, min z
inline constexpr std::size_t kWaveformStart = 227;   // 1.3+
inline constexpr std::size_t kFirstEvlr = 235;       // 1.4
inline constexpr std::size_t kEvlrCount = 243;
inline constexpr std::size_t kPointCount = 247;  // u64
inline constexpr std::size_t kByReturn = 255;    // u64[15]

inline constexpr std::size_t kHeaderSize12 = 227;
inline constexpr std::size_t kHeaderSize13 = 235;
inline constexpr std::size_t kHeaderSize14 = 375;
inline constexpr std::size_t kVlrHeaderSize = 54;

inline constexpr std::uint16_t kGlobalEncodingAdjustedGps = 1u << 0;
inline constexpr std::uint16_t kGlobalEncodingWkt = 1u << 4;
inline constexpr std::uint16_t kWktRecordId = 2112;
inline constexpr std::uint16_t kExtraBytesRecordId = 4;
inline constexpr std::uint16_t kWaveformDescriptorRecordId = 100;  // descriptor index 1 (+99)
inline constexpr std::uint16_t kWaveformPacketsRecordId = 65535;
inline constexpr std::uint16_t kGlobalEncodingWaveInternal = 1u << 1;
inline constexpr std::uint16_t kGlobalEncodingWaveExternal = 1u << 2;
inline constexpr std::size_t kWaveDescriptorSize = 26;
inline constexpr std::size_t kExtraBytesDescriptorSize = 192;
inline constexpr std::size_t kWavePacketFieldsSize = 29;  // index, offset, size, location, dx–dz
inline constexpr double kScanAngleUnit_deg = 0.006;  // scan angle unit, formats 6–10 (Table 13)

// Where formats 4, 5, 9 and 10 keep their wave packet fields (Tables 11, 12, 16, 17); 0: none.
inline constexpr std::size_t wave_fields_at(std::uint8_t format) {
    switch (format) {
        case 4:
            return 28;
        case 5:
            return 34;
        case 9:
            return 30;
        case 10:
            return 38;
        default:
            return 0;
    }
}

// Minimum record length of point formats 0–10 (Tables 7–17).
inline constexpr std::array<std::uint16_t, 11> kRecordLengths = {20, 28, 26, 34, 57, 63,
                                                                 30, 36, 38, 59, 67};

// A NUL-padded text field of n bytes.
inline std::string fixed_text(const std::uint8_t* p, std::size_t n) {
    std::size_t len = 0;
    while (len < n && p[len] != 0) ++len;
    return std::string(reinterpret_cast<const char*>(p), len);
}

// A NUL-padded text field of n bytes (longer text is cut).
inline void put_text(std::uint8_t* p, std::size_t n, const std::string& s) {
    std::memset(p, 0, n);
    std::memcpy(p, s.data(), s.size() < n ? s.size() : n);
}

inline void put_u8(std::uint8_t* p, std::uint8_t v) { p[0] = v; }
// On a little-endian host the bytes are the value's own, copied in one store (the encoder writes
// a dozen fields per point; GCC did not merge all the byte-by-byte stores); else byte by byte.
template <class T>
inline void put_le(std::uint8_t* p, T v) {
    if constexpr (std::endian::native == std::endian::little) {
        std::memcpy(p, &v, sizeof v);
    } else {
        for (std::size_t i = 0; i < sizeof v; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
    }
}
template <class T>
inline T get_le(const std::uint8_t* p) {
    T v = 0;
    if constexpr (std::endian::native == std::endian::little) {
        std::memcpy(&v, p, sizeof v);
    } else {
        for (std::size_t i = sizeof v; i-- > 0;) v = static_cast<T>((v << 8) | p[i]);
    }
    return v;
}

inline void put_u16(std::uint8_t* p, std::uint16_t v) { put_le(p, v); }
inline void put_u32(std::uint8_t* p, std::uint32_t v) { put_le(p, v); }
inline void put_u64(std::uint8_t* p, std::uint64_t v) { put_le(p, v); }
inline void put_i16(std::uint8_t* p, std::int16_t v) { put_u16(p, static_cast<std::uint16_t>(v)); }
inline void put_i32(std::uint8_t* p, std::int32_t v) { put_u32(p, static_cast<std::uint32_t>(v)); }
inline void put_f32(std::uint8_t* p, float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    put_u32(p, bits);
}
inline void put_f64(std::uint8_t* p, double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    put_u64(p, bits);
}

inline std::uint16_t get_u16(const std::uint8_t* p) { return get_le<std::uint16_t>(p); }
inline std::uint32_t get_u32(const std::uint8_t* p) { return get_le<std::uint32_t>(p); }
inline std::uint64_t get_u64(const std::uint8_t* p) { return get_le<std::uint64_t>(p); }
inline std::int16_t get_i16(const std::uint8_t* p) { return static_cast<std::int16_t>(get_u16(p)); }
inline std::int32_t get_i32(const std::uint8_t* p) { return static_cast<std::int32_t>(get_u32(p)); }
inline float get_f32(const std::uint8_t* p) {
    std::uint32_t bits = get_u32(p);
    float v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}
inline double get_f64(const std::uint8_t* p) {
    std::uint64_t bits = get_u64(p);
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
}

}  // namespace mirage::las::layout
