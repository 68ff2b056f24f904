// SPDX-License-Identifier: Apache-2.0
// Real captures (docs/wire-formats.md §6): our decoders read them without error, and an emulated
// sensor configured like the captured one produces the same packet statistics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mirage/pcap/pcap.hpp"
#include "mirage/velodyne/packetizer.hpp"
#include "test_paths.hpp"
#include "velodyne_capture_stats.hpp"
#include "velodyne_frames.hpp"
#include "velodyne_test_util.hpp"

namespace mirage::velodyne {
namespace {

CaptureStats stats_of_capture(const std::filesystem::path& path) {
    CaptureStatsBuilder b;
    for (const auto& d : pcap::read_udp(path.string()))
        b.add(stream_for_port(d.dst.port), d.time_ns, d.payload);
    return b.result();
}

// Our packetizer configured like the capture: model, return mode, rpm from the azimuth step;
// every pulse returns so that the data content is not empty.
CaptureStats stats_of_emulation(const CaptureStats& cap) {
    const ModelDescriptor& md = descriptor(*cap.model);
    const double rpm = std::clamp(cap.estimated_rpm(), md.rpm_min, md.rpm_max);
    const sensor::SensorModel s = test::preset_at(md, rpm);
    CaptureStatsBuilder b;
    PacketizerOptions o;
    o.fixed_position = GeoFix{37.143015, -121.663022, 28.8, 158.3, true};
    Packetizer pk(
        md, *cap.mode, s, core::parse_time("2012-12-11T22:02:44.473090Z"),
        [&](const wire::PacketView& v) { b.add(v); }, o);
    const std::uint64_t n = cap.data_packets * pk.pulses_per_packet();
    test::SyntheticOptions so;
    so.max_returns = 1;
    so.max_range_m = 60;
    pk.add(test::synthetic_returns(*s.scan, n, {}, so));
    pk.advance_to(n);
    pk.finish();
    return b.result();
}

void expect_same_structure(const CaptureStats& cap, const CaptureStats& emu) {
    EXPECT_EQ(emu.data_packets, cap.data_packets);
    EXPECT_EQ(emu.data_sizes, cap.data_sizes);
    EXPECT_EQ(emu.factory1, cap.factory1);
    EXPECT_EQ(emu.factory2, cap.factory2);
    EXPECT_EQ(emu.block_flags, cap.block_flags);
    EXPECT_EQ(emu.model, cap.model);
    EXPECT_EQ(emu.mode, cap.mode);
    EXPECT_EQ(emu.decode.errors(), 0u);
    // Azimuth step: same mean within 0.5 count, same most frequent step within one count.
    EXPECT_NEAR(emu.azimuth_step_counts.mean, cap.azimuth_step_counts.mean, 0.5);
    EXPECT_LE(std::abs(emu.azimuth_step_mode - cap.azimuth_step_mode), 1);
    EXPECT_NEAR(emu.estimated_rpm(), cap.estimated_rpm(), 0.01 * cap.estimated_rpm());
    // Timestamp step: the device's packet period in whole µs.
    EXPECT_EQ(emu.timestamp_step_us.min, cap.timestamp_step_us.min);
    EXPECT_EQ(emu.timestamp_step_us.max, cap.timestamp_step_us.max);
    EXPECT_NEAR(emu.timestamp_step_us.mean, cap.timestamp_step_us.mean, 0.5);
    // Packet rate from the send (capture) times, within 2 %.
    EXPECT_NEAR(emu.data_rate_hz, cap.data_rate_hz, 0.02 * cap.data_rate_hz);
}

TEST(VelodyneCapture, vlp16_example_decodes_without_error_and_matches_our_emulation) {
    MIRAGE_CAPTURE_OR_SKIP(path, "vlp16_example.pcap");
    const CaptureStats cap = stats_of_capture(path);
    std::printf("capture:\n%s", cap.describe().c_str());
    EXPECT_EQ(cap.data_packets, 84u);
    EXPECT_EQ(cap.position_packets, 0u);
    EXPECT_EQ(cap.decode.errors(), 0u);
    EXPECT_EQ(cap.decode[DecodeStatus::Ok], 84u);
    EXPECT_EQ(cap.model, Model::Vlp16);
    EXPECT_EQ(cap.mode, ReturnMode::Strongest);
    EXPECT_EQ(cap.factory1.at(0x37), 84u);
    EXPECT_EQ(cap.factory2.at(0x22), 84u);
    EXPECT_EQ(cap.block_flags.at(0xEEFF), 84u * 12u);
    EXPECT_EQ(cap.azimuth_step_mode, 40);
    EXPECT_GE(cap.azimuth_step_counts.min, 38);
    EXPECT_LE(cap.azimuth_step_counts.max, 42);
    EXPECT_EQ(cap.timestamp_step_us.min, 1327);
    EXPECT_EQ(cap.timestamp_step_us.max, 1328);
    EXPECT_EQ(cap.slots, 32'256u);
    EXPECT_EQ(cap.zero_distance_slots, 626u);

    // First return: block 0 slot 0 raw 2392 (4.784 m), reflectivity 48 (§6).
    const auto dg = pcap::read_udp(path.string(), kDataPort);
    DecodedPacket d;
    ASSERT_EQ(decode_data(dg.front().payload, &descriptor(Model::Vlp16), d), DecodeStatus::Ok);
    EXPECT_EQ(d.firing[0].raw_distance, 2392);
    EXPECT_FLOAT_EQ(d.firing[0].distance_m, 4.784f);
    EXPECT_EQ(d.firing[0].reflectivity, 48);
    // PCL's manual frame (−3.750, −2.700, −1.238) is FLU (y_pcl, −x_pcl) = (−2.700, 3.750).
    EXPECT_NEAR(d.firing[0].x, -2.700, 0.002);
    EXPECT_NEAR(d.firing[0].y, 3.750, 0.002);
    EXPECT_NEAR(d.firing[0].z, -1.238, 0.002);

    const CaptureStats emu = stats_of_emulation(cap);
    std::printf("emulation:\n%s", emu.describe().c_str());
    expect_same_structure(cap, emu);
}

TEST(VelodyneCapture, hdl32e_with_position_decodes_and_matches_our_emulation) {
    MIRAGE_CAPTURE_OR_SKIP(path, "hdl32e_with_position.pcap");
    const CaptureStats cap = stats_of_capture(path);
    std::printf("capture:\n%s", cap.describe().c_str());
    EXPECT_EQ(cap.data_packets, 876u);
    EXPECT_EQ(cap.position_packets, 100u);
    EXPECT_EQ(cap.decode.errors(), 0u);
    EXPECT_EQ(cap.model, Model::Hdl32e);
    EXPECT_EQ(cap.mode, ReturnMode::Strongest);
    EXPECT_EQ(cap.factory1.at(0x37), 876u);
    EXPECT_EQ(cap.factory2.at(0x21), 876u);
    EXPECT_EQ(cap.block_flags.at(0xEEFF), 876u * 12u);
    EXPECT_EQ(cap.timestamp_step_us.min, 552);
    EXPECT_EQ(cap.timestamp_step_us.max, 553);
    EXPECT_EQ(cap.slots, 336'384u);
    EXPECT_EQ(cap.zero_distance_slots, 84'327u);
    // Every position packet: valid checksum, an RMC sentence, the data packets' clock.
    EXPECT_EQ(cap.position[PositionStatus::Ok], 100u);
    EXPECT_EQ(cap.position_rmc, 100u);
    EXPECT_EQ(cap.position_sizes.at(512), 100u);
    EXPECT_GE(cap.position_vs_data_us.min, -1000.0);
    EXPECT_LE(cap.position_vs_data_us.max, 10'000.0);
    const auto pos = pcap::read_udp(path.string(), kPositionPort);
    DecodedPosition p;
    ASSERT_EQ(decode_position(pos.front().payload, p), PositionStatus::Ok);
    EXPECT_EQ(p.sentence.substr(0, 7), "$GPRMC,");
    EXPECT_EQ(p.year, 2012);
    EXPECT_EQ(p.month, 12);
    EXPECT_EQ(p.day, 11);
    // The sentence's minutes and seconds agree with the µs-past-hour clock (synchronised unit).
    EXPECT_NEAR(p.minute * 60 + p.second, p.timestamp_us / 1e6, 2.0);

    const CaptureStats emu = stats_of_emulation(cap);
    std::printf("emulation:\n%s", emu.describe().c_str());
    expect_same_structure(cap, emu);
    EXPECT_EQ(emu.position[PositionStatus::Ok], emu.position_packets);
    EXPECT_EQ(emu.position_rmc, emu.position_packets);
    ASSERT_EQ(emu.position_sizes.size(), 1u);
    EXPECT_EQ(emu.position_sizes.begin()->first, 512u);
    EXPECT_NEAR(emu.position_rate_hz, cap.position_rate_hz, 0.05 * cap.position_rate_hz);
    EXPECT_GE(emu.position_vs_data_us.min, -1000.0);
    EXPECT_LE(emu.position_vs_data_us.max, 10'000.0);
}

TEST(VelodyneCapture, hdl32e_frames_assemble_like_pcl_sweeps) {
    MIRAGE_CAPTURE_OR_SKIP(path, "hdl32e_with_position.pcap");
    std::vector<std::size_t> sizes;
    FrameAssembler fa(&descriptor(Model::Hdl32e),
                      [&](const Frame& f) { sizes.push_back(f.points.size()); });
    for (const auto& d : pcap::read_udp(path.string(), kDataPort)) fa.add(d.payload);
    fa.flush();
    EXPECT_EQ(fa.stats().gaps, 0u);
    EXPECT_EQ(fa.decode_counters().errors(), 0u);
    // PCL 1.13 (§5.1): 6 sweeps 16 295 / 43 908 / 44 157 / 44 150 / 44 590 / 44 541 points, the
    // trailing partial one never emitted. We split on the same block-azimuth wrap.
    ASSERT_GE(sizes.size(), 6u);
    const std::size_t pcl[] = {16'295, 43'908, 44'157, 44'150, 44'590, 44'541};
    for (std::size_t i = 0; i < 6; ++i) {
        std::printf("sweep %zu: %zu points (PCL %zu)\n", i, sizes[i], pcl[i]);
        EXPECT_EQ(sizes[i], pcl[i]);
    }
}

}  // namespace
}  // namespace mirage::velodyne
