// SPDX-License-Identifier: Apache-2.0
// NCOM stream and datagram decoding: splits, garbage, truncation, checksums, bad fields.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

#include "ncom_util.hpp"

namespace {

using namespace mirage::ncom;
using namespace mirage::ncom::test;
using mirage::nav::NavSample;

// Re-checksums a packet after a field was patched.
void repack(std::array<std::uint8_t, kPacketSize>& b) {
    b[22] = checksum(b, 1);
    b[61] = checksum(b, 2);
    b[71] = checksum(b, 3);
}

TEST(NcomStream, any_split_gives_the_same_samples) {
    const auto all = concat(make_packets(120, 1, kT0));
    Collect whole;
    whole.feed(all);
    ASSERT_EQ(whole.out.size(), 120U);
    std::mt19937_64 rng(2);
    for (std::size_t max_piece : {1UL, 2UL, 71UL, 73UL, 1000UL}) {
        Collect c;
        std::size_t off = 0;
        while (off < all.size()) {
            const std::size_t n = std::min<std::size_t>(1 + rng() % max_piece, all.size() - off);
            c.feed(std::span(all).subspan(off, n));
            off += n;
        }
        ASSERT_EQ(c.out.size(), 120U) << max_piece;
        for (std::size_t i = 0; i < 120; ++i) {
            EXPECT_EQ(c.out[i].t, whole.out[i].t);
            EXPECT_EQ(c.out[i].lat_deg, whole.out[i].lat_deg);
        }
        EXPECT_EQ(c.dec.counters().garbage_bytes, 0U);
        EXPECT_EQ(c.dec.counters().rejected(), 0U);
    }
}

TEST(NcomStream, garbage_between_packets_is_skipped_and_counted) {
    const auto pkts = make_packets(40, 3, kT0);
    std::mt19937_64 rng(4);
    std::vector<std::uint8_t> stream;
    std::uint64_t garbage = 0;
    for (const auto& p : pkts) {
        const std::size_t n = rng() % 50;
        for (std::size_t i = 0; i < n; ++i) {
            auto b = static_cast<std::uint8_t>(rng());
            stream.push_back(b);
        }
        garbage += n;
        stream.insert(stream.end(), p.begin(), p.end());
    }
    Collect c;
    c.feed(stream);
    EXPECT_EQ(c.out.size(), 40U);
    // Random 0xE7 bytes start false candidates that fail their checksums: garbage, not errors.
    EXPECT_EQ(c.dec.counters().garbage_bytes, garbage);
    EXPECT_EQ(c.dec.counters().bad_checksum, 0U);
}

TEST(NcomStream, corrupted_packet_in_sync_counts_bad_checksum) {
    auto pkts = make_packets(5, 5, kT0);
    pkts[2][30] ^= 0x10;
    Collect c;
    c.feed(concat(pkts));
    EXPECT_EQ(c.out.size(), 4U);
    EXPECT_EQ(c.dec.counters().bad_checksum, 1U);
    EXPECT_EQ(c.dec.counters().messages_ok, 4U);
}

TEST(NcomStream, each_checksum_is_checked) {
    for (std::size_t at : {5UL, 40UL, 66UL}) {  // covered by checksum 1, 2, 3 respectively
        auto pkts = make_packets(3, 6, kT0);
        pkts[1][at] ^= 0x01;
        // Keep the other checksums consistent with the change so only one fails.
        Collect c;
        c.feed(concat(pkts));
        EXPECT_EQ(c.dec.counters().bad_checksum, 1U) << at;
        EXPECT_EQ(c.out.size(), 2U) << at;
    }
}

TEST(NcomStream, truncated_packet_is_rejected_and_the_next_decodes) {
    auto pkts = make_packets(3, 7, kT0);
    std::vector<std::uint8_t> stream(pkts[0].begin(), pkts[0].end());
    stream.insert(stream.end(), pkts[1].begin(), pkts[1].begin() + 40);
    stream.insert(stream.end(), pkts[2].begin(), pkts[2].end());
    Collect c;
    c.feed(stream);
    EXPECT_EQ(c.out.size(), 2U);
    EXPECT_EQ(c.dec.counters().bad_checksum, 1U);  // one-byte sync: cut short looks corrupt
    Collect d;
    d.feed(std::span(pkts[0]).first(50));
    d.dec.finish();
    EXPECT_EQ(d.dec.counters().truncated, 1U);
    EXPECT_TRUE(d.out.empty());
}

TEST(NcomStream, nan_and_out_of_range_position_or_attitude_are_rejected) {
    auto pkts = make_packets(1, 8, kT0);
    const auto put_f64 = [](std::array<std::uint8_t, kPacketSize>& b, std::size_t at, double v) {
        const auto u = std::bit_cast<std::uint64_t>(v);
        for (int i = 0; i < 8; ++i)
            b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(u >> (8 * i));
    };
    std::vector<std::array<std::uint8_t, kPacketSize>> bad(6, pkts[0]);
    put_f64(bad[0], 23, std::numeric_limits<double>::quiet_NaN());  // lat NaN
    put_f64(bad[1], 23, 91.0 * std::numbers::pi / 180.0);           // lat > 90°
    put_f64(bad[2], 31, std::numeric_limits<double>::infinity());   // lon Inf
    bad[3][39] = 0x00;                                              // altitude f32 NaN (0x7FC00000)
    bad[3][40] = 0x00;
    bad[3][41] = 0xC0;
    bad[3][42] = 0x7F;
    write_i24(bad[4].data() + 55, 2'000'000);  // pitch 2 rad > 90°
    bad[5][1] = 0x70;                          // 0xEA70 = 60016 ms: past the minute
    bad[5][2] = 0xEA;
    Collect c;
    for (auto& b : bad) {
        repack(b);
        c.feed(b);
    }
    EXPECT_TRUE(c.out.empty());
    EXPECT_EQ(c.dec.counters().invalid_field, 6U);
    EXPECT_EQ(c.dec.counters().bad_checksum, 0U);
}

TEST(NcomStream, only_locked_packets_give_samples_others_are_counted) {
    auto pkts = make_packets(8, 9, kT0);
    const std::uint8_t statuses[] = {0, 1, 2, 3, 5, 6, 10, 22};
    for (std::size_t i = 0; i < pkts.size(); ++i) {
        pkts[i][21] = statuses[i];
        repack(pkts[i]);
    }
    Collect c;
    c.feed(concat(pkts));
    EXPECT_TRUE(c.out.empty());
    EXPECT_EQ(c.dec.ncom_counters().not_locked, 6U);
    EXPECT_EQ(c.dec.counters().unsupported, 2U);
    EXPECT_EQ(c.dec.counters().messages_ok, 6U);
}

TEST(NcomStream, datagrams_carry_one_or_more_packets) {
    const auto pkts = make_packets(7, 10, kT0);
    Collect c;
    c.datagram(pkts[0]);
    c.datagram(concat({pkts[1], pkts[2], pkts[3]}));
    EXPECT_EQ(c.out.size(), 4U);
    // Two packets and a 10-byte tail: the tail is truncated.
    auto two = concat({pkts[4], pkts[5]});
    two.insert(two.end(), pkts[6].begin(), pkts[6].begin() + 10);
    c.datagram(two);
    EXPECT_EQ(c.out.size(), 6U);
    EXPECT_EQ(c.dec.counters().truncated, 1U);
    // A chunk without the sync byte, and one with a bad checksum.
    auto junk = pkts[6];
    junk[0] = 0x00;
    c.datagram(junk);
    EXPECT_EQ(c.dec.counters().garbage_bytes, kPacketSize);
    junk = pkts[6];
    junk[10] ^= 0xFF;
    c.datagram(junk);
    EXPECT_EQ(c.dec.counters().bad_checksum, 1U);
    EXPECT_EQ(c.out.size(), 6U);
}

TEST(NcomStream, random_bytes_never_produce_a_sample) {
    std::mt19937_64 rng(11);
    std::vector<std::uint8_t> junk(100'000);
    for (auto& b : junk) b = static_cast<std::uint8_t>(rng());
    Collect c;
    c.feed(junk);
    c.datagram(junk);
    c.dec.finish();
    EXPECT_TRUE(c.out.empty());
    EXPECT_GT(c.dec.counters().garbage_bytes, 99'000U);
}

}  // namespace
