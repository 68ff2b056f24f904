// SPDX-License-Identifier: Apache-2.0
// Descriptors, CRC-64, lidar packet encode/decode and the decoder's statuses (docs/wire-formats.md
// §2).
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/ouster/decoder.hpp"
#include "mirage/ouster/descriptor.hpp"
#include "mirage/ouster/lidar_packet.hpp"

namespace mirage::ouster {
namespace {

Descriptor desc(int beams, Profile p, LidarMode m = {1024, 10},
                ProductLine line = ProductLine::OS1) {
    return make_descriptor(line, beams, m, p);
}

// A packet with random pixel values (representable in the profile) and consistent headers.
LidarPacket random_packet(const Descriptor& d, std::uint16_t first_mid, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    LidarPacket p;
    p.resize(d);
    p.header.frame_id = 1234;
    p.header.init_id = d.init_id;
    p.header.serial = d.serial;
    for (std::size_t c = 0; c < d.columns_per_packet; ++c) {
        auto& h = p.columns[c];
        h.timestamp_ns = 1'000'000'000ull + c * 97656ull;
        h.measurement_id = static_cast<std::uint16_t>(first_mid + c);
        h.frame_id = 1234;
        h.encoder_count = d.encoder_count(h.measurement_id);
        h.status = valid_column_status(d);
    }
    for (auto& px : p.pixels) {
        const auto v = rng();
        switch (d.profile) {
            case Profile::Legacy:
                px.range_mm = static_cast<std::uint32_t>(v & 0xFFFFF);
                px.flags = static_cast<std::uint8_t>((v >> 20) & 0xF);
                px.reflectivity = static_cast<std::uint16_t>(v >> 24);
                px.signal = static_cast<std::uint16_t>(v >> 40);
                px.nir = static_cast<std::uint16_t>(v >> 48);
                break;
            case Profile::Rng19Rfl8Sig16Nir16:
                px.range_mm = static_cast<std::uint32_t>(v & 0x7FFFF);
                px.flags = static_cast<std::uint8_t>((v >> 20) & 0x1F);
                px.reflectivity = static_cast<std::uint16_t>((v >> 25) & 0xFF);
                px.signal = static_cast<std::uint16_t>(v >> 40);
                px.nir = static_cast<std::uint16_t>(v >> 48);
                break;
            case Profile::Rng15Rfl8Nir8:
                px.range_mm = static_cast<std::uint32_t>(v & 0x7FFF) << 3;
                px.flags = static_cast<std::uint8_t>((v >> 20) & 1);
                px.reflectivity = static_cast<std::uint16_t>((v >> 25) & 0xFF);
                px.nir = static_cast<std::uint16_t>(((v >> 40) & 0xFF) << 4);
                break;
        }
    }
    return p;
}

std::vector<std::uint8_t> encode(const Descriptor& d, const LidarPacket& p) {
    std::vector<std::uint8_t> b(d.packet_bytes());
    EXPECT_TRUE(encode_lidar_packet(d, p, b));
    return b;
}

TEST(OusterDescriptor, packet_sizes_match_the_spec_table) {
    // docs/wire-formats.md §2.2.
    const struct {
        Profile p;
        std::size_t b32, b64, b128;
    } rows[] = {{Profile::Legacy, 6464, 12608, 24896},
                {Profile::Rng19Rfl8Sig16Nir16, 6400, 12544, 24832},
                {Profile::Rng15Rfl8Nir8, 2304, 4352, 8448}};
    for (const auto& r : rows) {
        EXPECT_EQ(desc(32, r.p).packet_bytes(), r.b32) << to_string(r.p);
        EXPECT_EQ(desc(64, r.p).packet_bytes(), r.b64) << to_string(r.p);
        EXPECT_EQ(desc(128, r.p).packet_bytes(), r.b128) << to_string(r.p);
    }
    EXPECT_EQ(desc(64, Profile::Legacy).column_bytes(), 788u);
}

TEST(OusterDescriptor, modes_rates_and_encoder_counts_follow_the_spec) {
    const auto d = desc(64, Profile::Legacy);
    EXPECT_EQ(d.packets_per_frame(), 64u);
    EXPECT_DOUBLE_EQ(d.column_period_ns(), 97656.25);
    EXPECT_EQ(d.encoder_count(1), 88u);
    EXPECT_EQ(d.encoder_count(800), 70400u);  // os1_64_legacy.pcap first column
    EXPECT_EQ(desc(64, Profile::Legacy, {2048, 10}).encoder_count(1), 44u);
    EXPECT_EQ(parse_lidar_mode("2048x10"), (LidarMode{2048, 10}));
    EXPECT_EQ(parse_profile("RNG15_RFL8_NIR8"), Profile::Rng15Rfl8Nir8);
    EXPECT_EQ(to_string(LidarMode{512, 20}), "512x20");
    EXPECT_EQ(d.prod_line(), "OS-1-64");
}

TEST(OusterDescriptor, bad_settings_throw_clear_errors) {
    try {
        parse_profile("RNG42");
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("ouster: unknown lidar profile 'RNG42'"),
                  std::string::npos);
    }
    EXPECT_THROW(parse_lidar_mode("4096x5"), ConfigError);  // SDK mode no product preset has
    EXPECT_THROW(make_descriptor(ProductLine::OS1, 48, {1024, 10}, Profile::Legacy), ConfigError);
    EXPECT_THROW(make_descriptor(ProductLine::OS1, 64, {1000, 10}, Profile::Legacy), ConfigError);
    EXPECT_THROW(make_descriptor(ProductLine::OS1, 64, {1024, 10}, Profile::Legacy, 24),
                 ConfigError);
    EXPECT_THROW(make_descriptor("vlp16", Profile::Legacy), ConfigError);
}

TEST(OusterDescriptor, beam_tables_come_from_the_presets) {
    const auto os1 = desc(64, Profile::Legacy);
    ASSERT_EQ(os1.altitude_deg.size(), 64u);
    EXPECT_DOUBLE_EQ(os1.altitude_deg[0], 16.611);  // gen-1 default (§2.7)
    EXPECT_DOUBLE_EQ(os1.azimuth_deg[1], 1.055);
    EXPECT_EQ(os1.pixel_shift_by_row()[0], 18);  // {18, 12, 6, 0} at 1024 columns (§2.7)
    EXPECT_EQ(os1.pixel_shift_by_row()[1], 12);
    EXPECT_EQ(os1.pixel_shift_by_row()[3], 0);
    const auto os2 = desc(128, Profile::Rng19Rfl8Sig16Nir16, {1024, 10}, ProductLine::OS2);
    EXPECT_DOUBLE_EQ(os2.altitude_deg[0], 10.76);  // os2_128_rng19.json
    EXPECT_DOUBLE_EQ(os2.beam_origin_mm, 13.762);
    EXPECT_DOUBLE_EQ(os2.lidar_to_sensor[11], 78.296);
    EXPECT_EQ(os2.pixel_shift_by_row()[0], 12);  // {12, 8, 4, 0} as in the capture's JSON
    EXPECT_EQ(os2.pixel_shift_by_row()[1], 8);
    const auto os0 = make_descriptor("os0-32-512x20", Profile::Rng15Rfl8Nir8);
    EXPECT_EQ(os0.line, ProductLine::OS0);
    EXPECT_DOUBLE_EQ(os0.altitude_deg.front(), 45.0);
    EXPECT_DOUBLE_EQ(os0.altitude_deg.back(), -45.0);
    EXPECT_DOUBLE_EQ(os0.beam_origin_mm, 27.67);
    EXPECT_EQ(os0.mode, (LidarMode{512, 20}));
}

TEST(OusterCrc, crc64_xz_check_value_and_packet_footer) {
    const std::string s = "123456789";
    const std::span<const std::uint8_t> bytes(reinterpret_cast<const std::uint8_t*>(s.data()),
                                              s.size());
    EXPECT_EQ(crc64_xz(bytes), 0x995DC9BBDF1939FAull);
    EXPECT_EQ(crc64_xz({}), 0ull);
    const auto d = desc(64, Profile::Rng19Rfl8Sig16Nir16);
    const auto b = encode(d, random_packet(d, 0, 1));
    std::uint64_t stored = 0;
    for (int i = 0; i < 8; ++i)
        stored |= std::uint64_t{b[b.size() - 8 + std::size_t(i)]} << (8 * i);
    EXPECT_EQ(stored, crc64_xz(std::span(b).first(b.size() - 8)));
}

TEST(OusterPacket, encode_decode_is_exact_for_every_profile_and_beam_count) {
    for (Profile p : {Profile::Legacy, Profile::Rng19Rfl8Sig16Nir16, Profile::Rng15Rfl8Nir8})
        for (int beams : {32, 64, 128}) {
            const auto d = desc(beams, p);
            const auto in = random_packet(d, 64, 7u + unsigned(beams));
            const auto b = encode(d, in);
            LidarPacket out;
            FooterCheck f;
            ASSERT_EQ(decode_lidar_packet(d, b, out, &f), DecodeStatus::Ok) << to_string(p);
            EXPECT_EQ(f, p == Profile::Legacy ? FooterCheck::None : FooterCheck::CrcValid);
            EXPECT_EQ(out.header.frame_id, 1234);
            if (p != Profile::Legacy) {
                EXPECT_EQ(out.header.init_id, d.init_id);
                EXPECT_EQ(out.header.serial, d.serial);
            }
            for (std::size_t c = 0; c < d.columns_per_packet; ++c) {
                EXPECT_EQ(out.columns[c].timestamp_ns, in.columns[c].timestamp_ns);
                EXPECT_EQ(out.columns[c].measurement_id, in.columns[c].measurement_id);
                EXPECT_EQ(out.columns[c].encoder_count, in.columns[c].encoder_count);
                EXPECT_TRUE(out.columns[c].valid());
            }
            std::size_t diff = 0;
            for (std::size_t i = 0; i < in.pixels.size(); ++i) {
                const auto &a = in.pixels[i], &o = out.pixels[i];
                diff += a.range_mm != o.range_mm || a.flags != o.flags ||
                        a.reflectivity != o.reflectivity || a.signal != o.signal || a.nir != o.nir;
            }
            EXPECT_EQ(diff, 0u) << to_string(p) << " " << beams;
        }
}

TEST(OusterPacket, fw2_footer_is_the_placeholder_and_decodes_as_such) {
    auto d = desc(128, Profile::Rng19Rfl8Sig16Nir16);
    d.footer = FooterKind::Fw2Placeholder;
    const auto b = encode(d, random_packet(d, 0, 3));
    const std::uint8_t tail[8] = {0xDE, 0xC0, 0x00, 0x00, 0xEF, 0xBE, 0xAD, 0xDE};
    for (int i = 0; i < 8; ++i) EXPECT_EQ(b[b.size() - 8 + std::size_t(i)], tail[i]);
    LidarPacket out;
    FooterCheck f;
    EXPECT_EQ(decode_lidar_packet(d, b, out, &f), DecodeStatus::Ok);
    EXPECT_EQ(f, FooterCheck::Placeholder);
}

TEST(OusterPacket, rng15_quantises_range_to_8_mm_and_nir_to_16) {
    const auto d = desc(32, Profile::Rng15Rfl8Nir8);
    LidarPacket p = random_packet(d, 0, 5);
    p.pixels[0].range_mm = 10'003;   // rounds to 10 000 (1250 × 8)
    p.pixels[1].range_mm = 10'005;   // rounds to 10 008
    p.pixels[2].nir = 1000;          // 62.5 × 16 → 63 × 16 = 1008
    p.pixels[3].range_mm = 400'000;  // beyond 262 136 mm: saturates
    LidarPacket out;
    ASSERT_EQ(decode_lidar_packet(d, encode(d, p), out), DecodeStatus::Ok);
    EXPECT_EQ(out.pixels[0].range_mm, 10'000u);
    EXPECT_EQ(out.pixels[1].range_mm, 10'008u);
    EXPECT_EQ(out.pixels[2].nir, 1008u);
    EXPECT_EQ(out.pixels[3].range_mm, 32767u * 8u);
}

// Each corruption yields its own status, in the documented order.
TEST(OusterDecoder, bad_packets_get_the_right_status_and_are_counted) {
    const auto d = desc(64, Profile::Rng19Rfl8Sig16Nir16);
    const auto good = encode(d, random_packet(d, 32, 11));
    const auto fix_crc = [&](std::vector<std::uint8_t> b) {
        const auto crc = crc64_xz(std::span(b).first(b.size() - 8));
        for (int i = 0; i < 8; ++i) b[b.size() - 8 + std::size_t(i)] = std::uint8_t(crc >> (8 * i));
        return b;
    };
    Decoder dec(d);
    EXPECT_EQ(dec.decode(good), DecodeStatus::Ok);
    EXPECT_EQ(dec.decode(std::span(good).first(good.size() - 1)), DecodeStatus::WrongSize);
    auto big = good;
    big.push_back(0);
    EXPECT_EQ(dec.decode(big), DecodeStatus::WrongSize);
    EXPECT_EQ(dec.decode({}), DecodeStatus::WrongSize);
    auto b = good;
    b[0] = 2;  // IMU packet type
    EXPECT_EQ(dec.decode(fix_crc(b)), DecodeStatus::BadPacketType);
    b = good;
    b[4] ^= 1;  // init ID
    EXPECT_EQ(dec.decode(fix_crc(b)), DecodeStatus::BadInitId);
    b = good;
    b[9] ^= 1;  // serial
    EXPECT_EQ(dec.decode(fix_crc(b)), DecodeStatus::BadSerial);
    b = good;
    b[1000] ^= 0x10;  // a pixel bit: only the CRC sees it
    EXPECT_EQ(dec.decode(b), DecodeStatus::BadCrc);
    b = good;
    b[32 + 10] = 0x02;  // column 0 status with a reserved bit
    EXPECT_EQ(dec.decode(fix_crc(b)), DecodeStatus::BadColumnStatus);
    b = good;
    b[32 + d.column_bytes() + 8] ^= 0x04;  // column 1 measurement ID no longer consecutive
    EXPECT_EQ(dec.decode(fix_crc(b)), DecodeStatus::BadMeasurementId);
    b = good;
    b[32 + 9] = 0x40;  // measurement ID ≥ W
    EXPECT_EQ(dec.decode(fix_crc(b)), DecodeStatus::BadMeasurementId);
    const auto& k = dec.counters();
    EXPECT_EQ(k.packets, 11u);
    EXPECT_EQ(k.by_status[size_t(DecodeStatus::Ok)], 1u);
    EXPECT_EQ(k.by_status[size_t(DecodeStatus::WrongSize)], 3u);
    EXPECT_EQ(k.by_status[size_t(DecodeStatus::BadMeasurementId)], 2u);
    EXPECT_EQ(k.errors(), 10u);
    // The CRC is checked after type and IDs: the good packet and the three field corruptions.
    EXPECT_EQ(k.crc_valid, 1u + 3u);
}

TEST(OusterDecoder, legacy_column_checks_frame_encoder_and_status) {
    const auto d = desc(32, Profile::Legacy);
    const auto good = encode(d, random_packet(d, 16, 13));
    const std::size_t cb = d.column_bytes();
    Decoder dec(d);
    auto b = good;
    b[cb + 10] ^= 1;  // column 1 frame ID
    EXPECT_EQ(dec.decode(b), DecodeStatus::BadFrameId);
    b = good;
    b[cb + 12] ^= 1;  // column 1 encoder count
    EXPECT_EQ(dec.decode(b), DecodeStatus::BadEncoderCount);
    b = good;
    b[cb - 1] = 0x7F;  // column 0 status neither 0 nor 0xFFFFFFFF
    EXPECT_EQ(dec.decode(b), DecodeStatus::BadColumnStatus);
    b = good;
    for (std::size_t i = 0; i < 4; ++i) b[cb - 4 + i] = 0;  // column 0 dropped: fields ignored
    b[8] = 0xFF;
    b[9] = 0xFF;
    EXPECT_EQ(dec.decode(b), DecodeStatus::Ok);
    EXPECT_EQ(dec.counters().dropped_columns, 1u);
    EXPECT_EQ(dec.packet().header.frame_id, 1234);
}

// ~20 000 random, truncated and bit-flipped packets: every one gets exactly one status, the
// counts add up, and (under ASan) nothing is read out of bounds.
TEST(OusterDecoder, random_truncated_and_bit_flipped_packets_are_all_accounted_for) {
    std::mt19937_64 rng(2024);
    std::uint64_t offered = 0;
    for (Profile p : {Profile::Legacy, Profile::Rng19Rfl8Sig16Nir16, Profile::Rng15Rfl8Nir8}) {
        const auto d = desc(32, p, {512, 10});
        Decoder dec(d);
        const auto good = encode(d, random_packet(d, 48, 17));
        std::uint64_t n = 0;
        for (int i = 0; i < 6700; ++i, ++n) {
            std::vector<std::uint8_t> b;
            switch (i % 4) {
                case 0:  // truncated or extended
                    b.assign(good.begin(), good.begin() + std::ptrdiff_t(rng() % good.size()));
                    if (rng() & 1) b.resize(good.size() + 1 + rng() % 64, 0xAB);
                    break;
                case 1:  // one to three bit flips
                    b = good;
                    for (int f = 0, nf = 1 + int(rng() % 3); f < nf; ++f)
                        b[rng() % b.size()] ^= std::uint8_t(1u << (rng() % 8));
                    break;
                case 2:  // random bytes of the right size
                    b.resize(good.size());
                    for (auto& x : b) x = std::uint8_t(rng());
                    break;
                default:
                    b = good;
            }
            dec.decode(b);
        }
        const auto& k = dec.counters();
        std::uint64_t sum = 0;
        for (auto c : k.by_status) sum += c;
        EXPECT_EQ(sum, n) << to_string(p);
        EXPECT_EQ(k.packets, n);
        EXPECT_GE(k.by_status[0], n / 4) << to_string(p);  // at least the untouched ones
        EXPECT_GT(k.by_status[size_t(DecodeStatus::WrongSize)], n / 5);
        if (p != Profile::Legacy) {  // a flipped bit never passes the CRC
            EXPECT_EQ(k.by_status[0], n / 4) << to_string(p);
        }
        offered += n;
    }
    EXPECT_EQ(offered, 20100u);
}

}  // namespace
}  // namespace mirage::ouster
