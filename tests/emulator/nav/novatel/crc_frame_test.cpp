// SPDX-License-Identifier: Apache-2.0
// CRC-32 check value and the real BESTPOSB frame of docs/nav-protocols.md §2.1.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <string_view>
#include <vector>

#include "mirage/novatel/crc32.hpp"
#include "mirage/novatel/decoder.hpp"
#include "mirage/novatel/frame.hpp"
#include "mirage/novatel/messages.hpp"

namespace {

using namespace mirage::novatel;

std::span<const std::uint8_t> as_bytes(std::string_view s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

// The BESTPOSB frame (header of docs/nav-protocols.md §2.1; whole frame as in novatel_edie's framer
// tests, MIT): 28-byte header, 72-byte body, CRC 0x89C3CE55.
const std::vector<std::uint8_t> kBestPosFrame = {
    0xAA, 0x44, 0x12, 0x1C, 0x2A, 0x00, 0x00, 0x20, 0x48, 0x00, 0x00, 0x00, 0xA3, 0xB4, 0x73,
    0x08, 0x98, 0x74, 0xA8, 0x13, 0x00, 0x00, 0x00, 0x02, 0xF6, 0xB1, 0xFF, 0xFF, 0x00, 0x00,
    0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0xFC, 0xAB, 0xE1, 0x82, 0x41, 0x93, 0x49, 0x40, 0xBA,
    0x32, 0x86, 0x8A, 0xF6, 0x81, 0x5C, 0xC0, 0x00, 0x10, 0xE5, 0xDF, 0x71, 0x23, 0x91, 0x40,
    0x00, 0x00, 0x88, 0xC1, 0x3D, 0x00, 0x00, 0x00, 0x24, 0x21, 0xA5, 0x3F, 0xF1, 0x8F, 0x8F,
    0x3F, 0x43, 0x74, 0x3C, 0x40, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x00, 0x15, 0x15, 0x15, 0x00, 0x00, 0x02, 0x11, 0x01, 0x55, 0xCE, 0xC3, 0x89};

LongHeader vector_header() {
    LongHeader h;
    h.message_id = 42;
    h.message_type = 0;
    h.port_address = 0x20;
    h.sequence = 0;
    h.idle_time = 0xA3;
    h.time_status = 0xB4;
    h.week = 2163;
    h.ms_of_week = 329'807'000;
    h.receiver_status = 0x02000000;
    h.reserved = 0xB1F6;
    h.software_build = 0xFFFF;
    return h;
}

BestPos vector_body() {
    BestPos m;
    m.solution_status = 0;
    m.position_type = kPosSingle;
    // §2.1 prints these rounded (51.150436744872°, −114.030672675183°, 1096.861 m); the frame
    // holds the doubles below, which the tests check against the printed values.
    m.lat_deg = std::bit_cast<double>(0x4049934182E1ABFCULL);
    m.lon_deg = std::bit_cast<double>(0xC05C81F68A8632BAULL);
    m.height_msl_m = std::bit_cast<double>(0x40912371DFE51000ULL);
    m.undulation_m = -17.0F;
    m.datum = 61;
    // σ fields are not in the reference table; their bit patterns come from the frame.
    m.lat_sigma_m = std::bit_cast<float>(0x3FA52124U);
    m.lon_sigma_m = std::bit_cast<float>(0x3F8F8FF1U);
    m.height_sigma_m = std::bit_cast<float>(0x403C7443U);
    m.svs_tracked = 21;
    m.svs_in_solution = 21;
    m.svs_l1 = 21;
    m.svs_multi = 0;
    m.reserved = 0;
    m.extended_status = 0x02;
    m.galileo_beidou_mask = 0x11;
    m.gps_glonass_mask = 0x01;
    return m;
}

TEST(NovatelCrc, check_value_of_123456789_is_0x2DFD2D88) {
    EXPECT_EQ(crc32(as_bytes("123456789")), 0x2DFD2D88U);
    EXPECT_NE(crc32(as_bytes("123456789")), 0xCBF43926U);  // not zlib's CRC-32
    EXPECT_EQ(crc32({}), 0U);
}

TEST(NovatelCrc, update_over_pieces_equals_crc_of_the_whole) {
    const auto all = as_bytes("The quick brown fox jumps over the lazy dog");
    for (std::size_t cut = 0; cut <= all.size(); cut += 5)
        EXPECT_EQ(crc32_update(crc32(all.first(cut)), all.subspan(cut)), crc32(all));
}

TEST(NovatelFrame, real_bestpos_frame_is_rebuilt_byte_for_byte_with_its_stored_crc) {
    const auto body = pack(vector_body());
    const std::vector<std::uint8_t> frame = frame_long(vector_header(), body);
    ASSERT_EQ(frame.size(), 104U);
    EXPECT_EQ(frame, kBestPosFrame);
    // CRC over header + body reproduces the stored 0x89C3CE55.
    EXPECT_EQ(crc32(std::span(frame).first(100)), 0x89C3CE55U);
    EXPECT_EQ(crc32(std::span(kBestPosFrame).first(100)), 0x89C3CE55U);
}

TEST(NovatelFrame, real_bestpos_frame_header_fields_parse) {
    const auto h = parse_long_header(kBestPosFrame);
    ASSERT_TRUE(h.has_value());
    EXPECT_EQ(h->message_id, 42);
    EXPECT_EQ(h->body_length, 72);
    EXPECT_EQ(h->week, 2163);
    EXPECT_EQ(h->ms_of_week, 329'807'000U);
    EXPECT_EQ(h->idle_time, 163);  // 81.5 %
    EXPECT_EQ(h->time_status, 180);
    const auto m = unpack_bestpos(std::span(kBestPosFrame).subspan(28, 72));
    ASSERT_TRUE(m.has_value());
    EXPECT_EQ(m->position_type, 16U);
    EXPECT_NEAR(m->lat_deg, 51.150436744872, 1e-12);
    EXPECT_NEAR(m->lon_deg, -114.030672675183, 1e-12);
    EXPECT_NEAR(m->height_msl_m, 1096.861, 0.5e-3);
    EXPECT_EQ(m->lat_deg, vector_body().lat_deg);
    EXPECT_EQ(m->height_msl_m, vector_body().height_msl_m);
    EXPECT_EQ(m->undulation_m, -17.0F);
    EXPECT_EQ(m->datum, 61U);
}

TEST(NovatelFrame, real_bestpos_frame_decodes_to_ellipsoidal_height_and_gps_time) {
    NovatelDecoder dec;
    std::vector<mirage::nav::NavSample> out;
    dec.feed(kBestPosFrame, [&](const mirage::nav::NavSample& s) { out.push_back(s); });
    ASSERT_EQ(out.size(), 1U);
    const auto& s = out[0];
    EXPECT_EQ(s.source, mirage::nav::Protocol::Novatel);
    EXPECT_EQ(s.fields, mirage::nav::NavSample::kTime | mirage::nav::NavSample::kPosition);
    EXPECT_EQ(s.lat_deg, vector_body().lat_deg);
    EXPECT_EQ(s.lon_deg, vector_body().lon_deg);
    EXPECT_NEAR(s.lat_deg, 51.150436744872, 1e-12);
    EXPECT_NEAR(s.lon_deg, -114.030672675183, 1e-12);
    EXPECT_EQ(s.height_m, vector_body().height_msl_m - 17.0);  // MSL + undulation
    EXPECT_NEAR(s.height_m, 1079.861, 0.5e-3);
    EXPECT_EQ(s.quality, mirage::nav::FixQuality::Autonomous);  // SINGLE
    EXPECT_EQ(s.satellites, 21);
    // Week 2163, 329 807 000 ms: GPS time as is (no leap seconds).
    const std::int64_t expect_ns = (2163LL * 604'800 + 329'807) * 1'000'000'000LL;
    EXPECT_EQ(s.t.time_since_epoch().count(), expect_ns);
    EXPECT_EQ(dec.counters().messages_ok, 1U);
    EXPECT_EQ(dec.counters().rejected(), 0U);
    EXPECT_EQ(dec.counters().garbage_bytes, 0U);
}

TEST(NovatelFrame, short_header_frame_has_12_byte_header_and_104_bytes_for_inspvas) {
    InsPvaS m;
    m.week = 2300;
    const auto body = pack(m);
    ShortHeader h;
    h.message_id = kInsPvaSId;
    h.week = 2300;
    h.ms_of_week = 1234;
    const auto f = frame_short(h, body);
    ASSERT_EQ(f.size(), 104U);
    EXPECT_EQ(f[2], 0x13);
    EXPECT_EQ(f[3], 88);
    const auto p = parse_short_header(f);
    ASSERT_TRUE(p.has_value());
    EXPECT_EQ(p->message_id, 508);
    EXPECT_EQ(p->week, 2300);
    EXPECT_EQ(p->ms_of_week, 1234U);
    EXPECT_EQ(crc32(std::span(f).first(100)),
              static_cast<std::uint32_t>(f[100] | f[101] << 8 | f[102] << 16) |
                  (static_cast<std::uint32_t>(f[103]) << 24));
}

}  // namespace
