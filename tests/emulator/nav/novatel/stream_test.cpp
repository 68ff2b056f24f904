// SPDX-License-Identifier: Apache-2.0
// The incremental decoder: random splits, garbage, truncation, bad CRC, bad fields.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "frames.hpp"
#include "mirage/novatel/crc32.hpp"
#include "mirage/novatel/encoder.hpp"
#include "sample_gen.hpp"

namespace {

using namespace mirage::novatel;
using namespace mirage::novatel::test;
using mirage::nav::NavSample;
namespace core = mirage::core;

// A mixed stream of the three logs; returns the frames.
std::vector<std::vector<std::uint8_t>> make_frames(int n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    NovatelEncoder enc;
    std::vector<std::vector<std::uint8_t>> frames;
    for (int i = 0; i < n; ++i) {
        const NavSample s = random_sample(rng);
        switch (i % 3) {
            case 0:
                frames.push_back(enc.inspvax(s));
                break;
            case 1:
                frames.push_back(enc.inspvas(s));
                break;
            default:
                frames.push_back(enc.bestpos(s));
                break;
        }
    }
    return frames;
}

std::vector<std::uint8_t> concat(const std::vector<std::vector<std::uint8_t>>& frames) {
    std::vector<std::uint8_t> all;
    for (const auto& f : frames) all.insert(all.end(), f.begin(), f.end());
    return all;
}

// Feeds `bytes` in random pieces of 1..max_piece bytes.
Collect feed_split(const std::vector<std::uint8_t>& bytes, std::mt19937_64& rng,
                   std::size_t max_piece) {
    Collect c;
    std::size_t off = 0;
    while (off < bytes.size()) {
        const std::size_t n = std::min<std::size_t>(1 + rng() % max_piece, bytes.size() - off);
        c.feed(std::span(bytes).subspan(off, n));
        off += n;
    }
    return c;
}

TEST(NovatelStream, any_split_gives_the_same_samples_as_one_feed) {
    const auto frames = make_frames(60, 1);
    const auto all = concat(frames);
    const auto whole = decode(all);
    ASSERT_EQ(whole.size(), 60U);
    std::mt19937_64 rng(2);
    for (std::size_t max_piece : {1UL, 3UL, 29UL, 200UL, 5000UL}) {
        Collect c = feed_split(all, rng, max_piece);
        ASSERT_EQ(c.out.size(), whole.size()) << max_piece;
        for (std::size_t i = 0; i < whole.size(); ++i) {
            EXPECT_EQ(c.out[i].t, whole[i].t);
            EXPECT_EQ(c.out[i].lat_deg, whole[i].lat_deg);
            EXPECT_EQ(c.out[i].heading_rad, whole[i].heading_rad);
        }
        EXPECT_EQ(c.dec.counters().messages_ok, 60U);
        EXPECT_EQ(c.dec.counters().garbage_bytes, 0U);
        EXPECT_EQ(c.dec.counters().rejected(), 0U);
    }
}

TEST(NovatelStream, garbage_between_frames_is_skipped_and_counted_exactly) {
    const auto frames = make_frames(30, 3);
    std::mt19937_64 rng(4);
    std::vector<std::uint8_t> stream;
    std::uint64_t garbage = 0;
    for (const auto& f : frames) {
        const std::size_t n = rng() % 40;
        for (std::size_t i = 0; i < n; ++i) {
            auto b = static_cast<std::uint8_t>(rng());
            if (b == kSync0) b = 0x00;  // no sync byte: exact count
            stream.push_back(b);
        }
        garbage += n;
        stream.insert(stream.end(), f.begin(), f.end());
    }
    Collect c = feed_split(stream, rng, 50);
    EXPECT_EQ(c.out.size(), 30U);
    EXPECT_EQ(c.dec.counters().garbage_bytes, garbage);
    EXPECT_EQ(c.dec.counters().rejected(), 0U);
}

TEST(NovatelStream, fully_random_garbage_and_false_syncs_lose_no_frame) {
    const auto frames = make_frames(30, 5);
    std::mt19937_64 rng(6);
    std::vector<std::uint8_t> stream;
    for (const auto& f : frames) {
        // A false sync announcing a long body that swallows the real frame behind it.
        const std::uint8_t fake[] = {0xAA, 0x44, 0x12, 0x1C, 0x2A, 0x00, 0x00, 0x20, 0x00, 0x01};
        stream.insert(stream.end(), std::begin(fake), std::end(fake));
        for (int i = 0; i < 20; ++i) stream.push_back(static_cast<std::uint8_t>(rng()));
        stream.insert(stream.end(), f.begin(), f.end());
    }
    Collect c = feed_split(stream, rng, 64);
    // The last false syncs still wait for their 256-byte bodies; finish() gives them up and
    // rescans what they held.
    EXPECT_LT(c.out.size(), 30U);
    c.dec.finish(c.fn());
    EXPECT_EQ(c.out.size(), 30U);
    EXPECT_EQ(c.dec.counters().messages_ok, 30U);
    // Each false sync is rejected once (its CRC fails with a real sync inside: truncated).
    EXPECT_GE(c.dec.counters().truncated + c.dec.counters().bad_checksum, 29U);
}

TEST(NovatelStream, corrupted_byte_counts_bad_checksum_and_neighbours_decode) {
    auto frames = make_frames(3, 7);
    frames[1][50] ^= 0x01;
    Collect c;
    c.feed(concat(frames));
    EXPECT_EQ(c.out.size(), 2U);
    EXPECT_EQ(c.dec.counters().bad_checksum, 1U);
    EXPECT_EQ(c.dec.counters().truncated, 0U);
    EXPECT_EQ(c.dec.counters().messages_ok, 2U);
    // The rest of the rejected frame was rescanned as garbage.
    EXPECT_EQ(c.dec.counters().garbage_bytes, frames[1].size() - 1);
}

TEST(NovatelStream, frame_cut_short_by_the_next_counts_truncated) {
    auto frames = make_frames(3, 8);
    frames[1].resize(60);
    Collect c;
    c.feed(concat(frames));
    EXPECT_EQ(c.out.size(), 2U);
    EXPECT_EQ(c.dec.counters().truncated, 1U);
    EXPECT_EQ(c.dec.counters().bad_checksum, 0U);
}

TEST(NovatelStream, partial_frame_at_end_of_stream_counts_truncated_on_finish) {
    auto frames = make_frames(2, 9);
    frames[1].resize(40);
    Collect c;
    c.feed(concat(frames));
    EXPECT_EQ(c.out.size(), 1U);
    EXPECT_EQ(c.dec.counters().truncated, 0U);  // may still arrive
    c.dec.finish();
    EXPECT_EQ(c.dec.counters().truncated, 1U);
}

TEST(NovatelStream, body_length_over_the_maximum_is_rejected_before_waiting) {
    std::vector<std::uint8_t> f = {0xAA, 0x44, 0x12, 0x1C, 0x2A, 0x00, 0x00, 0x20, 0xFF, 0xFF};
    Collect c;
    c.feed(f);  // 65535-byte body: not waited for
    const auto good = make_frames(1, 10)[0];
    c.feed(good);
    EXPECT_EQ(c.dec.counters().truncated, 1U);
    EXPECT_EQ(c.out.size(), 1U);
    EXPECT_EQ(c.dec.counters().garbage_bytes, f.size() - 1);
}

TEST(NovatelStream, unknown_message_id_with_valid_crc_counts_unsupported) {
    const std::uint8_t body[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    Collect c;
    c.feed(frame_long(header_at(101, 2300, 0), body));  // TIME
    ShortHeader h;
    h.message_id = 2264;  // CORRIMUS
    c.feed(frame_short(h, body));
    LongHeader resp = header_at(kBestPosId, 2300, 0);
    resp.message_type = 0x80;  // a command response, not the log
    c.feed(frame_long(resp, pack(BestPos{})));
    EXPECT_EQ(c.dec.counters().unsupported, 3U);
    EXPECT_EQ(c.dec.counters().messages_ok, 0U);
    EXPECT_TRUE(c.out.empty());
}

TEST(NovatelStream, nan_and_out_of_range_fields_are_rejected_and_counted) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<std::vector<std::uint8_t>> bad;
    {
        InsPvaX m = good_inspvax();
        m.lat_deg = nan;
        bad.push_back(frame(m));
        m = good_inspvax();
        m.lat_deg = 90.5;
        bad.push_back(frame(m));
        m = good_inspvax();
        m.vel_up_mps = inf;
        bad.push_back(frame(m));
        m = good_inspvax();
        m.pitch_deg = 95.0;
        bad.push_back(frame(m));
        m = good_inspvax();
        m.undulation_m = std::numeric_limits<float>::quiet_NaN();
        bad.push_back(frame(m));
    }
    {
        InsPvaS m = good_inspvas();
        m.lon_deg = -180.5;
        bad.push_back(frame(m));
        m = good_inspvas();
        m.seconds_of_week = nan;
        bad.push_back(frame(m));
        m = good_inspvas();
        m.seconds_of_week = 604'800.0;
        bad.push_back(frame(m));
    }
    {
        BestPos b;
        b.position_type = kPosSingle;
        b.height_msl_m = nan;
        bad.push_back(frame(b));
        b.height_msl_m = 0.0;
        bad.push_back(frame(b, 2300, 604'800'000));  // ms past the end of the week
    }
    // A supported id with a short body.
    const std::uint8_t short_body[10] = {};
    bad.push_back(frame_long(header_at(kInsPvaXId, 2300, 0), short_body));
    Collect c;
    for (const auto& f : bad) c.feed(f);
    EXPECT_TRUE(c.out.empty());
    EXPECT_EQ(c.dec.counters().invalid_field, bad.size());
    EXPECT_EQ(c.dec.counters().messages_ok, 0U);
    EXPECT_EQ(c.dec.counters().bad_checksum, 0U);
}

// A u16 or u32 week past core::kMaxGpsWeek has no place on the int64 ns timeline (found by
// fuzz_novatel as a signed overflow); the last representable week still decodes.
TEST(NovatelStream, weeks_past_the_timeline_are_refused_and_the_last_week_decodes) {
    constexpr auto last = static_cast<std::uint16_t>(core::kMaxGpsWeek);
    BestPos b;
    b.position_type = kPosSingle;
    InsPvaS s = good_inspvas();
    Collect c;
    c.feed(frame(b, last + 1, 0));
    c.feed(frame(good_inspvax(), 0xFFFF, 604'799'999));
    s.week = last + 1U;
    c.feed(frame(s));
    s.week = 0xFFFF'FFFFU;
    c.feed(frame(s));
    EXPECT_EQ(c.dec.counters().invalid_field, 4U);
    EXPECT_TRUE(c.out.empty());

    c.feed(frame(b, last, 604'799'999));
    s.week = last;
    s.seconds_of_week = 604'799.999'999'999;
    c.feed(frame(s));
    ASSERT_EQ(c.out.size(), 2U);
    constexpr std::int64_t kNsPerWeek = core::kSecondsPerWeek * core::kNsPerSecond;
    EXPECT_EQ(c.out[0].t.time_since_epoch().count(), (last + 1) * kNsPerWeek - 1'000'000);
    EXPECT_EQ(c.out[1].t.time_since_epoch().count(), (last + 1) * kNsPerWeek - 1);
}

TEST(NovatelStream, random_bytes_never_produce_a_sample) {
    std::mt19937_64 rng(11);
    std::vector<std::uint8_t> junk(200'000);
    for (auto& b : junk) b = static_cast<std::uint8_t>(rng());
    // Sprinkle sync sequences so the framing paths are exercised.
    for (std::size_t i = 0; i + 3 < junk.size(); i += 997) {
        junk[i] = 0xAA;
        junk[i + 1] = 0x44;
        junk[i + 2] = (i % 2) ? 0x12 : 0x13;
    }
    Collect c = feed_split(junk, rng, 300);
    c.dec.finish();
    EXPECT_TRUE(c.out.empty());
    EXPECT_EQ(c.dec.counters().messages_ok, 0U);
    EXPECT_GT(c.dec.counters().garbage_bytes, 190'000U);
}

}  // namespace
