// SPDX-License-Identifier: Apache-2.0
// The real captures of docs/wire-formats.md §6 decode without error, and our packetizer configured
// like each captured sensor produces a stream with the same structure (issue 3 item 5).
#include <gtest/gtest.h>

#include <cstdio>

#include "mirage/ouster/metadata.hpp"
#include "mirage/ouster/packetizer.hpp"
#include "mirage/pcap/pcap.hpp"
#include "ouster_capture_stats.hpp"
#include "ouster_test_util.hpp"
#include "test_paths.hpp"

namespace mirage::ouster {
namespace {

std::vector<TimedPacket> timed(const std::vector<pcap::UdpDatagram>& d) {
    std::vector<TimedPacket> out;
    for (const auto& x : d) out.push_back({x.time_ns, x.payload});
    return out;
}

std::vector<TimedPacket> timed(const std::vector<test::Captured>& c, wire::Stream s) {
    std::vector<TimedPacket> out;
    for (const auto& x : c)
        if (x.stream == s) out.push_back({x.time.time_since_epoch().count(), x.bytes});
    return out;
}

// Our stream for `d`: `frames` frames of empty columns, IMU at 100 Hz when asked.
CaptureStats emulated(const Descriptor& d, double frames, bool imu) {
    PacketizerConfig cfg;
    cfg.start = core::GpsTime(std::chrono::seconds(1'300'000'000));
    cfg.clock.mode = TimestampMode::InternalOsc;
    cfg.clock.power_on = cfg.start - std::chrono::seconds(765);
    if (imu) cfg.imu = [](core::GpsTime) { return ImuReading{}; };
    std::vector<test::Captured> out;
    OusterPacketizer pk(d, cfg, test::collect(out));
    pk.advance_to(static_cast<std::uint64_t>(frames * d.mode.columns) * d.beams);
    pk.finish();
    return capture_stats(d, timed(out, wire::Stream::Data), timed(out, wire::Stream::Imu));
}

void print(const char* what, const CaptureStats& s) {
    std::printf(
        "%-22s packets %4llu × %5zu B, errors %llu, crc %llu/placeholder %llu, col step %.0f ns, "
        "mid step %lld, enc step %lld, packets/frame %u, interval %.0f ns, imu %llu × %zu B "
        "every %.0f ns (ts step %.0f)\n",
        what, (unsigned long long)s.lidar_packets, s.lidar_packet_bytes,
        (unsigned long long)s.decode_errors, (unsigned long long)s.crc_valid,
        (unsigned long long)s.crc_placeholder, s.column_ts_step_ns,
        (long long)s.measurement_id_step, (long long)s.encoder_step, s.packets_per_frame,
        s.lidar_packet_interval_ns, (unsigned long long)s.imu_packets, s.imu_packet_bytes,
        s.imu_interval_ns, s.imu_ts_step_ns);
}

void expect_same_structure(const CaptureStats& real, const CaptureStats& ours) {
    EXPECT_EQ(ours.lidar_packet_bytes, real.lidar_packet_bytes);
    EXPECT_EQ(ours.columns_per_packet, real.columns_per_packet);
    EXPECT_EQ(ours.measurement_id_step, real.measurement_id_step);
    EXPECT_EQ(ours.encoder_step, real.encoder_step);
    EXPECT_EQ(ours.packets_per_frame, real.packets_per_frame);
    // Real column clocks jitter by ±3 µs around 97.6 µs; host arrival times by more.
    EXPECT_NEAR(ours.column_ts_step_ns, real.column_ts_step_ns, 0.01 * real.column_ts_step_ns);
    EXPECT_NEAR(ours.lidar_packet_interval_ns, real.lidar_packet_interval_ns,
                0.02 * real.lidar_packet_interval_ns);
    EXPECT_EQ(ours.imu_packet_bytes, real.imu_packet_bytes);
    if (real.imu_packets > 1) {
        EXPECT_NEAR(ours.imu_interval_ns, real.imu_interval_ns, 0.05 * real.imu_interval_ns);
        EXPECT_DOUBLE_EQ(ours.imu_ts_step_ns, real.imu_ts_step_ns);
    }
    EXPECT_EQ(ours.decode_errors, 0u);
}

TEST(OusterCapture, os1_64_legacy_decodes_cleanly_and_matches_our_stream) {
    MIRAGE_CAPTURE_OR_SKIP(pcap_path, "os1_64_legacy.pcap");
    MIRAGE_CAPTURE_OR_SKIP(json_path, "os1_64_legacy.json");
    const Descriptor d = load_metadata(json_path.string());  // FW 1.x flat: angles + mode only
    EXPECT_EQ(d.profile, Profile::Legacy);
    EXPECT_EQ(d.beams, 64);
    EXPECT_NEAR(d.altitude_deg[0], 16.856, 1e-9);
    const auto lidar = pcap::read_udp(pcap_path.string(), 7502);
    ASSERT_EQ(lidar.size(), 100u);
    const CaptureStats real = capture_stats(d, timed(lidar), {});
    print("os1_64_legacy.pcap", real);
    EXPECT_EQ(real.decode_errors, 0u);
    EXPECT_EQ(real.lidar_packet_bytes, 12608u);
    EXPECT_EQ(real.encoder_step, 88);
    EXPECT_EQ(real.packets_per_frame, 64u);  // frame 12073 is complete
    EXPECT_EQ(real.measurement_id_gaps, 0u);

    // Points: the capture's first column through §2.8 (sensor frame) has plausible ranges.
    Decoder dec(d);
    std::vector<OusterPoint> pts;
    for (const auto& p : lidar) {
        ASSERT_EQ(dec.decode(p.payload), DecodeStatus::Ok);
        dec.points(PointFrame::Sensor, pts);
    }
    EXPECT_EQ(pts.size(), 92'270u);  // non-zero ranges (§6)
    EXPECT_EQ(dec.counters().frames, 3u);

    Descriptor ours = make_descriptor(ProductLine::OS1, 64, {1024, 10}, Profile::Legacy);
    const CaptureStats emu = emulated(ours, 1.6, false);
    print("ours os1-64-1024x10", emu);
    expect_same_structure(real, emu);
}

TEST(OusterCapture, os2_128_rng19_with_imu_decodes_cleanly_and_matches_our_stream) {
    MIRAGE_CAPTURE_OR_SKIP(pcap_path, "os2_128_rng19.pcap");
    MIRAGE_CAPTURE_OR_SKIP(json_path, "os2_128_rng19.json");
    const Descriptor d = load_metadata(json_path.string());
    EXPECT_EQ(d.line, ProductLine::OS2);
    EXPECT_EQ(d.profile, Profile::Rng19Rfl8Sig16Nir16);
    EXPECT_EQ(d.serial, 992210000957ull);
    EXPECT_EQ(d.init_id, 5431293u);
    EXPECT_EQ(d.footer, FooterKind::Fw2Placeholder);
    const auto lidar = pcap::read_udp(pcap_path.string(), 7502);
    const auto imu = pcap::read_udp(pcap_path.string(), 7503);
    ASSERT_EQ(lidar.size(), 64u);
    ASSERT_EQ(imu.size(), 10u);
    const CaptureStats real = capture_stats(d, timed(lidar), timed(imu));
    print("os2_128_rng19.pcap", real);
    EXPECT_EQ(real.decode_errors, 0u);
    EXPECT_EQ(real.crc_placeholder, 64u);  // FW 2.3: footer placeholder, never a CRC failure
    EXPECT_EQ(real.crc_valid, 0u);
    EXPECT_EQ(real.lidar_packet_bytes, 24832u);
    EXPECT_EQ(real.imu_packet_bytes, 48u);
    EXPECT_DOUBLE_EQ(real.imu_ts_step_ns, 10'000'000.0);

    // A decoder configured with the wrong serial rejects the packets by ID (SDK validate()).
    Descriptor other = d;
    other.serial += 1;
    Decoder wrong(other);
    EXPECT_EQ(wrong.decode(lidar[0].payload), DecodeStatus::BadSerial);

    ImuPacket first;
    ASSERT_TRUE(decode_imu_packet(imu[0].payload, first));
    EXPECT_NEAR(first.accel_g[0], 0.0083, 1e-4);  // §2.6
    EXPECT_NEAR(first.accel_g[2], 1.0210, 1e-4);
    EXPECT_NEAR(first.gyro_dps[2], -0.458, 1e-3);

    // Ours: same descriptor (identity from the JSON, FW 2.x footer), 1.2 frames, IMU on.
    const CaptureStats emu = emulated(d, 1.2, true);
    print("ours os2-128-1024x10", emu);
    expect_same_structure(real, emu);
    EXPECT_EQ(emu.crc_placeholder, emu.lidar_packets);
    // And a FW 3.x-like stream carries valid CRCs.
    Descriptor fw3 = d;
    fw3.footer = FooterKind::Crc64;
    const CaptureStats emu3 = emulated(fw3, 0.2, false);
    EXPECT_EQ(emu3.crc_valid, emu3.lidar_packets);
    EXPECT_GT(emu3.lidar_packets, 0u);
}

}  // namespace
}  // namespace mirage::ouster
