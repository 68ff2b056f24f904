// SPDX-License-Identifier: Apache-2.0
// Frame assembly over a stream with packets dropped mid-revolution.
#include <gtest/gtest.h>

#include "velodyne_frames.hpp"
#include "mirage/velodyne/packetizer.hpp"
#include "velodyne_test_util.hpp"

namespace mirage::velodyne {
namespace {

struct Stream {
    std::vector<test::CollectedPacket> packets;
    std::uint64_t pulses_per_rev = 0;
};

// Every pulse returns (10 m), VLP-16 at 600 rpm, `packets` packets.
Stream full_returns(std::uint64_t packets) {
    const ModelDescriptor& md = descriptor(Model::Vlp16);
    const sensor::SensorModel s = test::preset_at(md, 600);
    Stream st;
    PacketizerOptions o;
    o.position_packets = false;
    Packetizer pk(md, ReturnMode::Strongest, s, core::GpsTime{}, test::collect_into(st.packets), o);
    const std::uint64_t n = packets * pk.pulses_per_packet();
    std::vector<core::PointRecord> pts(static_cast<std::size_t>(n));
    std::vector<sensor::PulseSpec> spec(pts.size());
    s.scan->pulses(0, spec.size(), spec.data());
    for (std::uint64_t k = 0; k < n; ++k) {
        auto& p = pts[static_cast<std::size_t>(k)];
        p.pulse = k;
        p.channel = spec[static_cast<std::size_t>(k)].channel;
        p.range_m = 10.0f;
        p.n_laser = 100;
    }
    pk.add(pts);
    pk.advance_to(n);
    return st;
}

TEST(VelodyneFrames, dropped_packets_mid_frame_restart_assembly_and_count_the_gap) {
    const std::uint64_t total = 330;  // ≈ 4.4 revolutions of 75.35 packets
    const Stream st = full_returns(total);
    ASSERT_EQ(st.packets.size(), total);
    std::vector<Frame> frames;
    FrameAssembler fa(&descriptor(Model::Vlp16), [&](const Frame& f) { frames.push_back(f); });
    std::uint64_t fed = 0;
    for (std::uint64_t i = 0; i < total; ++i) {
        if (i >= 160 && i < 167) continue;  // 7 packets lost in the middle of revolution 2
        EXPECT_EQ(fa.add(st.packets[i].bytes), DecodeStatus::Ok);
        ++fed;
    }
    fa.flush();
    EXPECT_EQ(fa.stats().gaps, 1u);
    EXPECT_EQ(fa.stats().missing_packets, 7u);
    EXPECT_EQ(fa.stats().packets, fed);
    // Revolutions 0 (no wrap before it), 1, 2 split in two by the gap, 3, 4 (partial, flushed).
    ASSERT_EQ(frames.size(), 6u);
    const bool complete[] = {false, true, false, false, true, false};
    std::uint64_t points = 0;
    for (std::size_t f = 0; f < frames.size(); ++f) {
        SCOPED_TRACE("frame " + std::to_string(f));
        EXPECT_EQ(frames[f].complete, complete[f]);
        points += frames[f].points.size();
        if (frames[f].complete) {
            // One revolution: 1808.4 sequences of 16 lasers, split on whole blocks of 2 sequences.
            EXPECT_GE(frames[f].points.size(), 904u * 32u);
            EXPECT_LE(frames[f].points.size(), 905u * 32u);
            EXPECT_EQ(frames[f].points.size() % 32, 0u);
        }
    }
    EXPECT_EQ(points, fed * 384u);
    std::printf("frames %zu, points of the complete ones %zu and %zu, gap of %llu packets\n",
                frames.size(), frames[1].points.size(), frames[4].points.size(),
                static_cast<unsigned long long>(fa.stats().missing_packets));
}

TEST(VelodyneFrames, undecodable_packets_are_counted_and_skipped) {
    const Stream st = full_returns(4);
    FrameAssembler fa(&descriptor(Model::Vlp16), {});
    std::vector<std::uint8_t> bad = st.packets[1].bytes;
    bad.pop_back();
    EXPECT_EQ(fa.add(st.packets[0].bytes), DecodeStatus::Ok);
    EXPECT_EQ(fa.add(bad), DecodeStatus::WrongSize);
    EXPECT_EQ(fa.add(st.packets[1].bytes), DecodeStatus::Ok);
    EXPECT_EQ(fa.decode_counters()[DecodeStatus::WrongSize], 1u);
    EXPECT_EQ(fa.decode_counters()[DecodeStatus::Ok], 2u);
    EXPECT_EQ(fa.stats().gaps, 0u);
}

}  // namespace
}  // namespace mirage::velodyne
