// SPDX-License-Identifier: Apache-2.0
// The shared resynchronising buffer with a toy framing (sync 0x7E, length byte, sum byte):
// splits, garbage and fillers, frames hidden behind false syncs, incomplete frames, the cap.
#include "mirage/nav/resync_buffer.hpp"

#include <gtest/gtest.h>

#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace {

using mirage::nav::ByteKind;
using mirage::nav::FrameLength;
using mirage::nav::ResyncBuffer;
using Bytes = std::vector<std::uint8_t>;

constexpr std::uint8_t kSync = 0x7E;
constexpr std::size_t kMaxFrame = 64;

// 7E <n> <n payload bytes> <sum of payload mod 256>.
Bytes frame(const Bytes& payload) {
    Bytes f{kSync, static_cast<std::uint8_t>(payload.size())};
    for (const std::uint8_t b : payload) f.push_back(b);
    f.push_back(static_cast<std::uint8_t>(std::accumulate(payload.begin(), payload.end(), 0u)));
    return f;
}

Bytes cat(std::initializer_list<Bytes> parts) {
    Bytes out;
    for (const auto& p : parts)
        for (const std::uint8_t b : p) out.push_back(b);
    return out;
}

// A toy decoder on the buffer: frames whose sum fails are rejected and rescanned from the next
// byte; '\n' is a filler; a length byte over 60 is not a frame.
struct Toy {
    ResyncBuffer buf{kMaxFrame};
    std::uint64_t garbage = 0, bad_sum = 0;
    std::vector<Bytes> frames;
    std::vector<std::uint64_t> offsets;

    void feed(std::span<const std::uint8_t> bytes) {
        buf.append(bytes);
        buf.drain(
            garbage,
            [](std::uint8_t b) {
                if (b == kSync) return ByteKind::Sync;
                return b == '\n' ? ByteKind::Filler : ByteKind::Garbage;
            },
            [](std::span<const std::uint8_t> rest) {
                if (rest.size() < 2) return FrameLength::need_more();
                if (rest[1] > 60) return FrameLength::skip(1, true);
                const std::size_t total = 3u + rest[1];
                return rest.size() < total ? FrameLength::need_more()
                                           : FrameLength::complete(total);
            },
            [&](std::span<const std::uint8_t> f) -> std::size_t {
                const auto sum = std::accumulate(f.begin() + 2, f.end() - 1, 0u);
                if (static_cast<std::uint8_t>(sum) != f.back()) {
                    ++bad_sum;
                    return 1;
                }
                frames.emplace_back(f.begin() + 2, f.end() - 1);
                offsets.push_back(buf.offset());
                return f.size();
            });
    }
};

TEST(ResyncBuffer, any_split_gives_the_same_frames_and_counters) {
    const Bytes stream = cat({frame({1, 2, 3}),
                              {0x00, 0x11, '\n'},
                              frame({}),
                              frame({9, 9}),
                              {kSync, 70},
                              frame({4}),
                              {0x22}});
    Toy whole;
    whole.feed(stream);
    ASSERT_EQ(whole.frames.size(), 4u);
    EXPECT_EQ(whole.frames[0], (Bytes{1, 2, 3}));
    EXPECT_EQ(whole.frames[3], (Bytes{4}));
    EXPECT_EQ(whole.offsets, (std::vector<std::uint64_t>{0, 9, 12, 19}));
    // 00, 11, the false sync 7E (length 70), 70 itself, the trailing 22: '\n' is a filler.
    EXPECT_EQ(whole.garbage, 5u);
    std::mt19937 rng(7);
    for (int run = 0; run < 50; ++run) {
        Toy t;
        for (std::size_t off = 0; off < stream.size();) {
            const std::size_t n = std::min<std::size_t>(1 + rng() % 5, stream.size() - off);
            t.feed(std::span(stream).subspan(off, n));
            off += n;
        }
        EXPECT_EQ(t.frames, whole.frames);
        EXPECT_EQ(t.offsets, whole.offsets);
        EXPECT_EQ(t.garbage, whole.garbage);
    }
}

TEST(ResyncBuffer, a_frame_behind_a_rejected_candidate_is_still_found) {
    // A sync byte followed by a "length" that swallows a real frame: the candidate's sum fails,
    // the buffer rescans from the byte after its sync and finds the real one.
    const Bytes real = frame({5, 6});
    const Bytes stream = cat({{kSync, 4}, real, {0x00}});
    Toy t;
    t.feed(stream);
    EXPECT_EQ(t.bad_sum, 1u);
    ASSERT_EQ(t.frames.size(), 1u);
    EXPECT_EQ(t.frames[0], (Bytes{5, 6}));
    EXPECT_EQ(t.offsets[0], 2u);
    EXPECT_EQ(t.garbage, 2u);  // the 4 after the rejected sync, the trailing 00
}

TEST(ResyncBuffer, waits_for_an_incomplete_frame_and_clear_drops_it) {
    const Bytes f = frame({1, 2, 3, 4});
    Toy t;
    t.feed(std::span(f).first(f.size() - 1));
    EXPECT_TRUE(t.frames.empty());
    EXPECT_EQ(t.buf.size(), f.size() - 1);
    t.feed(std::span(f).last(1));
    EXPECT_EQ(t.frames.size(), 1u);
    EXPECT_EQ(t.buf.size(), 0u);
    t.feed(std::span(f).first(3));
    t.buf.clear();
    EXPECT_EQ(t.buf.size(), 0u);
    EXPECT_EQ(t.buf.offset(), f.size() + 3);  // cleared bytes still advance the stream offset
    EXPECT_EQ(t.garbage, 0u);
}

TEST(ResyncBuffer, a_candidate_longer_than_the_cap_is_no_frame) {
    // A framer that always wants more: with kMaxFrame bytes buffered the sync is dropped as
    // garbage, so the buffer stays bounded however long the stream runs.
    ResyncBuffer buf(kMaxFrame);
    std::uint64_t garbage = 0;
    const Bytes syncs(1000, kSync);
    for (std::size_t off = 0; off < syncs.size(); off += 10) {
        buf.append(std::span(syncs).subspan(off, 10));
        buf.drain(
            garbage, [](std::uint8_t) { return ByteKind::Sync; },
            [](std::span<const std::uint8_t>) { return FrameLength::need_more(); },
            [](std::span<const std::uint8_t> f) { return f.size(); });
        EXPECT_LT(buf.size(), kMaxFrame);
    }
    EXPECT_EQ(garbage, syncs.size() - (kMaxFrame - 1));
}

TEST(ResyncBuffer, compacts_a_long_stream_without_losing_frames) {
    Toy t;
    std::size_t n = 0;
    for (int i = 0; i < 5000; ++i) {
        const Bytes f = cat({frame({static_cast<std::uint8_t>(i), 1, 2}), {0x33}});
        // Two halves, so a frame is often split across a compaction.
        t.feed(std::span(f).first(4));
        t.feed(std::span(f).subspan(4));
        n += f.size();
    }
    EXPECT_EQ(t.frames.size(), 5000u);
    EXPECT_EQ(t.frames[4999][0], static_cast<std::uint8_t>(4999));
    EXPECT_EQ(t.garbage, 5000u);
    EXPECT_EQ(t.buf.offset(), n);
}

}  // namespace
