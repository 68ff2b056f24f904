// SPDX-License-Identifier: Apache-2.0
// `mirage emulate` end to end: settings a model lacks fail clearly; the pcap it writes decodes
// without error at the device's packet rates; pcap send times follow the sensor clock.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cli_run.hpp"
#include "mirage/ouster/decoder.hpp"
#include "mirage/ouster/descriptor.hpp"
#include "mirage/pcap/pcap.hpp"
#include "mirage/velodyne/data_packet.hpp"
#include "mirage/velodyne/model.hpp"
#include "mirage/velodyne/position_packet.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

TEST(EmulateCli, settings_the_model_lacks_are_config_errors_naming_the_setting) {
    struct Case {
        std::string args, expect;
    };
    const Case cases[] = {
        {"--sensor vlp16 --rpm 2000", "rpm"},
        {"--sensor vlp16 --return-mode twice", "return-mode"},
        {"--sensor os1-64-1024x10 --profile RNG99", "RNG99"},
        {"--sensor os1-64-1024x10 --return-mode dual", "single-return"},
        {"--sensor os1-64-1024x10 --rpm 600", "--rpm"},
        {"--sensor als-mirror", "no wire format"},
        {"--sensor os1-64-4096x10", "os1-64-4096x10"},
    };
    for (const auto& c : cases) {
        const auto r = run_mirage("emulate --pose 0,0,2 --duration 0.1 --pcap /dev/null " + c.args);
        EXPECT_NE(r.exit_code, 0) << c.args;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.args << ": " << r.output;
    }
    const auto unbounded =
        run_mirage("emulate --pose 0,0,2 --as-fast-as-possible --pcap /dev/null");
    EXPECT_EQ(unbounded.exit_code, 2);
    EXPECT_NE(unbounded.output.find("needs --duration"), std::string::npos) << unbounded.output;
    const auto none = run_mirage("emulate --pose 0,0,2 --duration 0.1");
    EXPECT_EQ(none.exit_code, 2);
    EXPECT_NE(none.output.find("--to"), std::string::npos) << none.output;
}

TEST(EmulateCli, vlp16_pcap_has_the_device_packet_rates_and_decodes_cleanly) {
    TempDir tmp;
    const auto pcap = tmp.file("vlp.pcap");
    const auto r = run_mirage(
        "emulate --sensor vlp16 --trajectory demo-car --duration 1 "
        "--as-fast-as-possible --no-status --pcap " +
        pcap);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(std::filesystem::exists(tmp.file("vlp.yaml")));  // calibration alongside
    const auto data = pcap::read_udp(pcap, 2368);
    const auto pos = pcap::read_udp(pcap, 8308);
    // VLP-16 strongest: 754 data packets/s (1 s of firings = 753.5 whole packets).
    EXPECT_NEAR(double(data.size()), 754.0, 1.0);
    EXPECT_GT(pos.size(), 0u);
    const auto& model = velodyne::descriptor(velodyne::Model::Vlp16);
    std::size_t ok = 0;
    velodyne::DecodedPacket dp;
    for (const auto& d : data)
        ok += velodyne::decode_data(d.payload, &model, dp) == velodyne::DecodeStatus::Ok;
    EXPECT_EQ(ok, data.size());
    velodyne::DecodedPosition p;
    std::size_t rmc = 0;
    for (const auto& d : pos)
        rmc += velodyne::decode_position(d.payload, p) == velodyne::PositionStatus::Ok && p.rmc &&
               p.fix_valid;
    EXPECT_EQ(rmc, pos.size());  // the demo town is georeferenced: every fix is valid
    // Packet send times follow the firing clock: 1 s of data spans 1 s within one packet.
    const double span_s = double(data.back().time_ns - data.front().time_ns) * 1e-9;
    EXPECT_NEAR(span_s, 1.0, 2.0 / 754.0);
}

// A VLP-16 with the waveform detector (2 returns) before a leaf (ρ 0.3, τ 0.6) at x = 8 m and a
// wall at x = 16 m, in dual mode: the packets carry the detector's echoes, the leaf (the
// stronger: 0.3/8² against 0.5·0.6²/16²) as strongest and the wall as last (time-resolved.md §8).
TEST(EmulateCli, dual_packets_carry_the_waveform_detector_s_strongest_and_last_echoes) {
    TempDir tmp;
    const auto scene = tmp.file("leaf.yaml");
    std::ofstream(scene) << "materials:\n  leaf: {reflectance: 0.3, transmission: 0.6}\n"
                            "  wall: {reflectance: 0.5}\nobjects:\n"
                            "  - {type: plane, material: leaf, size: [40, 40], transform: "
                            "{translate: [8, 0, 0], rotate_deg: [0, 90, 0]}}\n"
                            "  - {type: plane, material: wall, size: [80, 80], transform: "
                            "{translate: [16, 0, 0], rotate_deg: [0, 90, 0]}}\n";
    const auto sensor = tmp.file("vlp16-waveform.yaml");
    std::ofstream(sensor) << "base: vlp16\nreceiver: {max_returns: 2}\ndetector: {type: linear}\n";
    const auto pcap = tmp.file("dual.pcap");
    const auto r = run_mirage("emulate --scene " + scene + " --sensor " + sensor +
                              " --pose 0,0,0 --return-mode dual --duration 0.02 --no-noise "
                              "--as-fast-as-possible --pcap " +
                              pcap);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto* model = &velodyne::descriptor(velodyne::Model::Vlp16);
    std::size_t pairs = 0, worst_count = 0;
    double worst = 0;
    for (const auto& p : pcap::read_udp(pcap)) {
        if (p.dst.port != 2368) continue;
        velodyne::DecodedPacket d;
        ASSERT_EQ(velodyne::decode_data(p.payload, model, d), velodyne::DecodeStatus::Ok);
        for (std::size_t b = 0; b + 1 < velodyne::kBlocksPerPacket; b += 2)
            for (std::size_t c = 0; c < velodyne::kSlotsPerBlock; ++c) {
                const auto& last = d.firing[32 * b + c];
                const auto& strongest = d.firing[32 * (b + 1) + c];
                const double az =
                    last.azimuth_deg > 180 ? last.azimuth_deg - 360 : last.azimuth_deg;
                if (std::abs(az) > 40 || last.distance_m == 0) continue;
                ++pairs;
                const double e = std::max(std::abs(last.x - 16.0), std::abs(strongest.x - 8.0));
                worst = std::max(worst, e);
                worst_count += e > 0.05;
            }
    }
    std::printf("%zu dual pairs in front: last at the wall, strongest at the leaf, worst %.4f m\n",
                pairs, worst);
    EXPECT_GT(pairs, 1000u);
    EXPECT_EQ(worst_count, 0u);
}

TEST(EmulateCli, a_stream_with_port_zero_is_not_produced_and_settings_fail_before_files) {
    TempDir tmp;
    const auto pcap = tmp.file("nopos.pcap");
    const auto r = run_mirage(
        "emulate --sensor vlp16 --pose 0,0,1.8 --duration 0.2 "
        "--as-fast-as-possible --no-status --position-port 0 --pcap " +
        pcap);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_GT(pcap::read_udp(pcap, 2368).size(), 100u);
    EXPECT_EQ(pcap::read_udp(pcap, 8308).size(), 0u);
    EXPECT_EQ(pcap::read_udp(pcap, 0).size(), pcap::read_udp(pcap, 2368).size());  // nothing else
    // A setting the model lacks is reported before any output file exists.
    const auto bad = tmp.file("bad.pcap");
    EXPECT_EQ(
        run_mirage("emulate --sensor vlp16 --pose 0,0,1.8 --duration 0.2 --rpm 2000 --pcap " + bad)
            .exit_code,
        2);
    EXPECT_FALSE(std::filesystem::exists(bad));
}

TEST(EmulateCli, ouster_rng19_pcap_has_lidar_and_imu_packets_at_device_rates) {
    TempDir tmp;
    const auto pcap = tmp.file("os.pcap");
    const auto r = run_mirage(
        "emulate --sensor os1-64-1024x10 --profile RNG19_RFL8_SIG16_NIR16 --pose 0,0,1.8 "
        "--duration 1 --as-fast-as-possible --no-status --pcap " +
        pcap);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(std::filesystem::exists(tmp.file("os.json")));  // metadata alongside
    const auto lidar = pcap::read_udp(pcap, 7502);
    const auto imu = pcap::read_udp(pcap, 7503);
    EXPECT_EQ(lidar.size(), 640u);  // 1024 columns / 16 per packet × 10 Hz
    EXPECT_NEAR(double(imu.size()), 100.0, 1.0);
    ouster::Decoder dec(
        ouster::make_descriptor("os1-64-1024x10", ouster::Profile::Rng19Rfl8Sig16Nir16));
    std::size_t ok = 0;
    for (const auto& d : lidar) ok += dec.decode(d.payload) == ouster::DecodeStatus::Ok;
    EXPECT_EQ(ok, lidar.size());
}

}  // namespace
}  // namespace mirage::test
