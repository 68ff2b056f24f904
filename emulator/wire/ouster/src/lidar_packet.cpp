// SPDX-License-Identifier: Apache-2.0
#include "mirage/ouster/lidar_packet.hpp"

#include <algorithm>
#include <array>
#include <cstring>

#include <lzma.h>

#include "byte_io.hpp"

namespace mirage::ouster {
namespace {

constexpr std::uint32_t kLegacyRangeMask = (1u << 20) - 1;
constexpr std::uint32_t kRng19RangeMask = (1u << 19) - 1;
constexpr std::uint32_t kRng15Max = (1u << 15) - 1;  // × 8 mm

void encode_pixel(const Descriptor& d, const Pixel& px, std::uint8_t* p) {
    switch (d.profile) {
        case Profile::Legacy: {
            const std::uint32_t r = std::min(px.range_mm, kLegacyRangeMask);
            put_u32(p, r | (std::uint32_t{px.flags} & 0xFu) << 28);
            put_u16(p + 4, px.reflectivity);
            put_u16(p + 6, px.signal);
            put_u16(p + 8, px.nir);
            put_u16(p + 10, 0);
            break;
        }
        case Profile::Rng19Rfl8Sig16Nir16: {
            const std::uint32_t r = std::min(px.range_mm, kRng19RangeMask);
            put_u32(p, r | (std::uint32_t{px.flags} & 0x1Fu) << 19);
            p[4] = static_cast<std::uint8_t>(std::min<std::uint16_t>(px.reflectivity, 255));
            p[5] = 0;
            put_u16(p + 6, px.signal);
            put_u16(p + 8, px.nir);
            p[10] = 0;
            p[11] = 0;
            break;
        }
        case Profile::Rng15Rfl8Nir8: {
            const std::uint32_t r = std::min((px.range_mm + 4) >> 3, kRng15Max);
            put_u16(p, static_cast<std::uint16_t>(r | (std::uint32_t{px.flags} & 1u) << 15));
            p[2] = static_cast<std::uint8_t>(std::min<std::uint16_t>(px.reflectivity, 255));
            p[3] = static_cast<std::uint8_t>(std::min((px.nir + 8) >> 4, 255));
            break;
        }
    }
}

Pixel decode_pixel(Profile profile, const std::uint8_t* p) {
    Pixel px;
    switch (profile) {
        case Profile::Legacy: {
            const std::uint32_t w = get_u32(p);
            px.range_mm = w & kLegacyRangeMask;
            px.flags = static_cast<std::uint8_t>(w >> 28);
            px.reflectivity = get_u16(p + 4);
            px.signal = get_u16(p + 6);
            px.nir = get_u16(p + 8);
            break;
        }
        case Profile::Rng19Rfl8Sig16Nir16: {
            const std::uint32_t w = get_u32(p);
            px.range_mm = w & kRng19RangeMask;
            px.flags = static_cast<std::uint8_t>((w >> 19) & 0x1Fu);
            px.reflectivity = p[4];
            px.signal = get_u16(p + 6);
            px.nir = get_u16(p + 8);
            break;
        }
        case Profile::Rng15Rfl8Nir8: {
            const std::uint16_t w = get_u16(p);
            px.range_mm = std::uint32_t{w & 0x7FFFu} << 3;
            px.flags = static_cast<std::uint8_t>(w >> 15);
            px.reflectivity = p[2];
            px.nir = static_cast<std::uint16_t>(std::uint32_t{p[3]} << 4);
            break;
        }
    }
    return px;
}

}  // namespace

std::uint64_t crc64_xz(std::span<const std::uint8_t> bytes) {
    // §2.5: CRC-64/XZ, which is exactly liblzma's lzma_crc64 (initial value 0 = start).
    return lzma_crc64(bytes.data(), bytes.size(), 0);
}

const char* to_string(DecodeStatus s) {
    constexpr std::array<const char*, kDecodeStatusCount> kNames = {
        "ok",      "wrong size",        "bad packet type",    "bad init id",  "bad serial",
        "bad crc", "bad column status", "bad measurement id", "bad frame id", "bad encoder count"};
    const auto i = static_cast<std::size_t>(s);
    return i < kNames.size() ? kNames[i] : "?";
}

void LidarPacket::resize(const Descriptor& d) {
    columns.resize(d.columns_per_packet);
    pixels.resize(std::size_t{d.columns_per_packet} * d.beams);
}

std::uint32_t valid_column_status(const Descriptor& d) {
    return d.profile == Profile::Legacy ? 0xFFFFFFFFu : 1u;
}

bool encode_lidar_packet(const Descriptor& d, const LidarPacket& p, std::span<std::uint8_t> out) {
    const std::size_t size = d.packet_bytes();
    const std::size_t H = d.beams;
    if (out.size() != size || p.columns.size() < d.columns_per_packet ||
        p.pixels.size() < std::size_t{d.columns_per_packet} * H)
        return false;
    std::uint8_t* b = out.data();
    const bool legacy = d.profile == Profile::Legacy;
    if (!legacy) {
        std::memset(b, 0, 32);
        put_u16(b, p.header.packet_type);
        put_u16(b + 2, p.header.frame_id);
        put_uint(b + 4, p.header.init_id, 3);
        put_uint(b + 7, p.header.serial, 5);
        b[12] = p.header.alert_flags;
        b[16] = p.header.thermal_shutdown_countdown;
        b[17] = p.header.shot_limiting_countdown;
        b[18] = static_cast<std::uint8_t>(p.header.thermal_shutdown_status & 0xFu);
        b[19] = static_cast<std::uint8_t>(p.header.shot_limiting_status & 0xFu);
    }
    const std::size_t col_bytes = d.column_bytes();
    const std::size_t px_bytes = d.pixel_bytes();
    for (std::size_t c = 0; c < d.columns_per_packet; ++c) {
        std::uint8_t* col = b + d.packet_header_bytes() + c * col_bytes;
        const ColumnHeader& h = p.columns[c];
        put_u64(col, h.timestamp_ns);
        put_u16(col + 8, h.measurement_id);
        if (legacy) {
            put_u16(col + 10, h.frame_id);
            put_u32(col + 12, h.encoder_count);
            put_u32(col + col_bytes - 4, h.status);
        } else {
            put_u16(col + 10, static_cast<std::uint16_t>(h.status));
        }
        std::uint8_t* px = col + d.column_header_bytes();
        for (std::size_t r = 0; r < H; ++r) encode_pixel(d, p.pixels[c * H + r], px + r * px_bytes);
    }
    if (!legacy) {
        std::uint8_t* foot = b + size - 32;
        std::memset(foot, 0, 32);
        const std::uint64_t word =
            d.footer == FooterKind::Crc64 ? crc64_xz({b, size - 8}) : kFw2FooterWord;
        put_u64(b + size - 8, word);
    }
    return true;
}

DecodeStatus decode_lidar_packet(const Descriptor& d, std::span<const std::uint8_t> bytes,
                                 LidarPacket& out, FooterCheck* footer) {
    if (footer) *footer = FooterCheck::None;
    const std::size_t size = d.packet_bytes();
    if (bytes.size() != size) return DecodeStatus::WrongSize;
    out.resize(d);
    const std::uint8_t* b = bytes.data();
    const bool legacy = d.profile == Profile::Legacy;
    if (!legacy) {
        PacketHeader& h = out.header;
        h.packet_type = get_u16(b);
        h.frame_id = get_u16(b + 2);
        h.init_id = static_cast<std::uint32_t>(get_uint(b + 4, 3));
        h.serial = get_uint(b + 7, 5);
        h.alert_flags = b[12];
        h.thermal_shutdown_countdown = b[16];
        h.shot_limiting_countdown = b[17];
        h.thermal_shutdown_status = static_cast<std::uint8_t>(b[18] & 0xFu);
        h.shot_limiting_status = static_cast<std::uint8_t>(b[19] & 0xFu);
        if (h.packet_type != kPacketTypeLidar) return DecodeStatus::BadPacketType;
        // SDK validate(): IDs are only compared when the packet carries them (non-zero).
        if (h.init_id != 0 && h.init_id != (d.init_id & 0xFFFFFFu)) return DecodeStatus::BadInitId;
        if (h.serial != 0 && h.serial != (d.serial & 0xFFFFFFFFFFull))
            return DecodeStatus::BadSerial;
        out.footer_word = get_u64(b + size - 8);
        bool zero_pad = true;
        for (std::size_t i = size - 32; i < size - 8; ++i) zero_pad = zero_pad && b[i] == 0;
        FooterCheck check;
        if (zero_pad && out.footer_word == kFw2FooterWord) {
            check = FooterCheck::Placeholder;
        } else {
            check = crc64_xz({b, size - 8}) == out.footer_word ? FooterCheck::CrcValid
                                                               : FooterCheck::CrcInvalid;
        }
        if (footer) *footer = check;
        if (check == FooterCheck::CrcInvalid) return DecodeStatus::BadCrc;
    } else {
        out.header = PacketHeader{};
        out.footer_word = 0;
    }
    const std::size_t col_bytes = d.column_bytes();
    const std::size_t px_bytes = d.pixel_bytes();
    const std::size_t H = d.beams;
    bool have_prev = false;
    std::uint16_t prev_mid = 0, first_frame = 0;
    for (std::size_t c = 0; c < d.columns_per_packet; ++c) {
        const std::uint8_t* col = b + d.packet_header_bytes() + c * col_bytes;
        ColumnHeader& h = out.columns[c];
        h.timestamp_ns = get_u64(col);
        h.measurement_id = get_u16(col + 8);
        if (legacy) {
            h.frame_id = get_u16(col + 10);
            h.encoder_count = get_u32(col + 12);
            h.status = get_u32(col + col_bytes - 4);
            if (h.status != 0 && h.status != 0xFFFFFFFFu) return DecodeStatus::BadColumnStatus;
        } else {
            h.frame_id = out.header.frame_id;
            h.encoder_count = d.encoder_count(h.measurement_id);
            h.status = get_u16(col + 10);
            // Only bit 0 is defined (valid); other bits set mean this is not a column header.
            if (h.status > 1) return DecodeStatus::BadColumnStatus;
        }
        const std::uint8_t* px = col + d.column_header_bytes();
        for (std::size_t r = 0; r < H; ++r)
            out.pixels[c * H + r] = decode_pixel(d.profile, px + r * px_bytes);
        if (!h.valid()) continue;  // dropped column: its fields are meaningless
        if (h.measurement_id >= d.mode.columns) return DecodeStatus::BadMeasurementId;
        if (have_prev && h.measurement_id != prev_mid + c) return DecodeStatus::BadMeasurementId;
        if (legacy) {
            if (!have_prev) first_frame = h.frame_id;
            if (h.frame_id != first_frame) return DecodeStatus::BadFrameId;
            if (h.encoder_count != d.encoder_count(h.measurement_id))
                return DecodeStatus::BadEncoderCount;
        }
        if (!have_prev) {
            if (h.measurement_id < c) return DecodeStatus::BadMeasurementId;
            // Measurement ID the packet's column 0 would carry.
            prev_mid = static_cast<std::uint16_t>(h.measurement_id - c);
            have_prev = true;
        }
    }
    if (legacy && have_prev) out.header.frame_id = first_frame;
    return DecodeStatus::Ok;
}

}  // namespace mirage::ouster
