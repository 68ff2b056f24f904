// SPDX-License-Identifier: Apache-2.0
// Entity State PDUs against the layout of docs/dis.md §1: fields at their offsets, big-endian;
// each check in its order with its counter; the filter; timestamps and the hourly rollover.
#include "mirage/dis/entity_state.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace mirage::dis {
namespace {

EntityState sample_state() {
    EntityState s;
    s.version = 7;
    s.exercise = 3;
    s.timestamp = encode_timestamp(1234.5, true);
    s.id = {42, 7, 1001};
    s.force = 1;
    s.velocity = {1.5f, -2.25f, 0.125f};
    s.location = {4'000'000.25, 700'000.5, 4'900'000.75};
    s.psi = 0.5f;
    s.theta = -0.25f;
    s.phi = 0.125f;
    s.appearance = 0x01020304;
    s.dr_algorithm = 4;
    s.dr_acceleration = {0.5f, 0.25f, -9.75f};
    s.dr_angular_velocity = {0.01f, -0.02f, 0.03f};
    std::memcpy(s.marking.data(), "MIRAGE-1", 8);
    s.capabilities = 0xA0B0C0D0;
    return s;
}

std::uint64_t be(const std::vector<std::uint8_t>& b, std::size_t at, std::size_t n) {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < n; ++i) v = (v << 8) | b[at + i];
    return v;
}

// The bytes sit where IEEE 1278.1 puts them, most significant first.
TEST(DisEntityState, fields_lie_at_their_offsets_big_endian) {
    const auto b = encode(sample_state());
    ASSERT_EQ(b.size(), 144u);
    EXPECT_EQ(b[0], 7);
    EXPECT_EQ(b[1], 3);
    EXPECT_EQ(b[2], 1);  // Entity State
    EXPECT_EQ(b[3], 1);  // entity information family
    EXPECT_EQ(be(b, 8, 2), 144u);
    EXPECT_EQ(be(b, 12, 2), 42u);
    EXPECT_EQ(be(b, 14, 2), 7u);
    EXPECT_EQ(be(b, 16, 2), 1001u);
    EXPECT_EQ(b[18], 1);
    EXPECT_EQ(be(b, 36, 4), std::bit_cast<std::uint32_t>(1.5f));
    EXPECT_EQ(be(b, 48, 8), std::bit_cast<std::uint64_t>(4'000'000.25));
    EXPECT_EQ(be(b, 64, 8), std::bit_cast<std::uint64_t>(4'900'000.75));
    EXPECT_EQ(be(b, 72, 4), std::bit_cast<std::uint32_t>(0.5f));
    EXPECT_EQ(be(b, 84, 4), 0x01020304u);
    EXPECT_EQ(b[88], 4);
    EXPECT_EQ(be(b, 112, 4), std::bit_cast<std::uint32_t>(-9.75f));
    EXPECT_EQ(be(b, 124, 4), std::bit_cast<std::uint32_t>(0.03f));
    EXPECT_EQ(b[128], 1);  // ASCII marking
    EXPECT_EQ(b[129], 'M');
    EXPECT_EQ(be(b, 140, 4), 0xA0B0C0D0u);
}

TEST(DisEntityState, a_pdu_decodes_to_what_was_encoded) {
    const EntityState s = sample_state();
    EntityStateDecoder d;
    EntityState t;
    ASSERT_EQ(d.decode(encode(s), t), Status::Ok);
    EXPECT_EQ(t.location, s.location);
    EXPECT_EQ(t.velocity, s.velocity);
    EXPECT_EQ(t.psi, s.psi);
    EXPECT_EQ(t.theta, s.theta);
    EXPECT_EQ(t.phi, s.phi);
    EXPECT_EQ(t.dr_algorithm, 4);
    EXPECT_EQ(t.dr_acceleration, s.dr_acceleration);
    EXPECT_EQ(t.dr_angular_velocity, s.dr_angular_velocity);
    EXPECT_TRUE(t.id == s.id);
    EXPECT_EQ(t.timestamp, s.timestamp);
    EXPECT_EQ(t.marking, s.marking);
    EXPECT_EQ(d.counters().messages_ok, 1u);
}

// Each failure in the checks' order (length, header, ids, fields), each with its counter; a
// version 6 PDU and one with variable parameter records (and bytes past its length) decode.
TEST(DisEntityState, each_check_rejects_in_order_and_counts) {
    const auto good = encode(sample_state());
    EntityState t;
    const auto status = [&](std::vector<std::uint8_t> b, Filter f = {}) {
        EntityStateDecoder d(f);
        return d.decode(b, t);
    };
    EXPECT_EQ(status({good.begin(), good.begin() + 11}), Status::Short);
    EXPECT_EQ(status({good.begin(), good.begin() + 143}), Status::Short);
    auto v = good;
    v[0] = 5;
    EXPECT_EQ(status(v), Status::BadVersion);
    v = good;
    v[0] = 6;
    EXPECT_EQ(status(v), Status::Ok);
    v = good;
    v[2] = 2;  // Fire PDU
    EXPECT_EQ(status(v), Status::OtherPdu);
    v = good;
    v[3] = 2;
    EXPECT_EQ(status(v), Status::OtherPdu);
    v = good;
    v[9] = 160;  // length 160 with N = 0
    v.resize(160);
    EXPECT_EQ(status(v), Status::BadLength);
    v = good;
    v[19] = 2;
    v[9] = 176;
    EXPECT_EQ(status(v), Status::Short);  // the header says 176 bytes: 144 arrived
    v.resize(180, 0);                     // two records and 4 bytes past the PDU
    EXPECT_EQ(status(v), Status::Ok);
    EXPECT_EQ(status(good, {4, {}}), Status::OtherExercise);
    EXPECT_EQ(status(good, {3, EntityId{42, 7, 1002}}), Status::OtherEntity);
    EXPECT_EQ(status(good, {3, EntityId{42, 7, 1001}}), Status::Ok);
    v = good;
    std::memset(v.data() + 48, 0xFF, 8);  // a NaN location
    EXPECT_EQ(status(v), Status::BadField);
    v = good;
    v[48] = 0x7F;  // 1.6e308 m from the Earth's centre
    v[49] = 0xE0;
    EXPECT_EQ(status(v), Status::BadField);
    v = good;
    v[88] = 10;  // no such dead-reckoning algorithm
    EXPECT_EQ(status(v), Status::BadField);

    EntityStateDecoder d({3, EntityId{42, 7, 1001}});
    v = good;
    v[2] = 2;
    for (const auto& b : {good, v, std::vector<std::uint8_t>(good.begin(), good.begin() + 20)})
        d.decode(b, t);
    EXPECT_EQ(d.counters().messages_ok, 1u);
    EXPECT_EQ(d.dis_counters().other_pdu, 1u);
    EXPECT_EQ(d.counters().truncated, 1u);
}

// 2³¹ units an hour: 1234.5 s past the hour within one unit (1.68 µs); the lowest bit says
// absolute; intervals across the hour's rollover are short, not an hour long.
TEST(DisEntityState, timestamps_count_the_hour_and_roll_over) {
    const std::uint32_t raw = encode_timestamp(1234.5, true);
    EXPECT_EQ(raw & 1u, 1u);
    EXPECT_NEAR(decode_timestamp(raw).seconds_past_hour, 1234.5, 3600.0 / 2147483648.0);
    EXPECT_TRUE(decode_timestamp(raw).absolute);
    EXPECT_FALSE(decode_timestamp(encode_timestamp(10, false)).absolute);
    EXPECT_NEAR(decode_timestamp(0xFFFFFFFEu).seconds_past_hour, 3600.0, 1e-5);
    EXPECT_NEAR(decode_timestamp(encode_timestamp(-0.5, false)).seconds_past_hour, 3599.5, 2e-6);
    EXPECT_EQ(encode_timestamp(std::nan(""), true), 1u);
    EXPECT_DOUBLE_EQ(seconds_between(3599.0, 1.0), 2.0);
    EXPECT_DOUBLE_EQ(seconds_between(1.0, 3599.0), -2.0);
    EXPECT_DOUBLE_EQ(seconds_between(100.0, 100.25), 0.25);
}

}  // namespace
}  // namespace mirage::dis
