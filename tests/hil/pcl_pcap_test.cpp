// SPDX-License-Identifier: Apache-2.0
// PCL 1.13 (VLPGrabber, HDLGrabber) decodes a pcap written by `mirage emulate` inside a closed
// room: every point lies on the room's planes and every revolution holds the model's firings.
#include <gtest/gtest.h>
#include <pcl/io/hdl_grabber.h>
#include <pcl/io/vlp_grabber.h>

#include <chrono>
#include <memory>

#include "mirage/pcap/pcap.hpp"
#include "mirage/sensor/sensor.hpp"
#include "mirage/velodyne/data_packet.hpp"
#include "pcl_db_xml.hpp"
#include "pcl_harness.hpp"
#include "sweep_checks.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

using namespace std::chrono_literals;

constexpr double kDurationS = 0.6;  // 6 revolutions at 600 rpm → PCL emits 5 sweeps

struct PcapCase {
    const char* sensor;
    velodyne::Model model;
    bool noise;
    // VLPGrabber interpolates slots 16–31 by a truncated half step (0.015°); HDLGrabber uses
    // the rounded block azimuth only (0.005°).
    double azimuth_tol_deg;
    velodyne::ReturnMode mode = velodyne::ReturnMode::Strongest;
};

// HDL-32E: PCL's built-in table; HDL-64E: the db.xml converted from Mirage's calibration file.
std::unique_ptr<pcl::HDLGrabber> grabber_for(velodyne::Model m, const std::string& pcap,
                                             const std::string& db_xml) {
    if (m == velodyne::Model::Vlp16) return std::make_unique<pcl::VLPGrabber>(pcap);
    return std::make_unique<pcl::HDLGrabber>(db_xml, pcap);
}

void run_pcap_case(const PcapCase& c) {
    TempDir dir;
    const Room room;
    room.write(dir.file("room.yaml"));
    SensorSetup setup;
    setup.model = c.model;
    const bool dual = c.mode == velodyne::ReturnMode::Dual;
    if (dual && c.model != velodyne::Model::Vlp16) setup.points_per_firing = 2;
    const std::string pcap_path = dir.file("x.pcap");

    auto args = emulate_args(setup, c.sensor, dir.file("room.yaml"), c.noise);
    args.insert(args.end(), {"--as-fast-as-possible", "--duration", "0.6", "--pcap", pcap_path});
    if (dual) args.insert(args.end(), {"--return-mode", "dual"});
    const bool hdl64 = c.model == velodyne::Model::Hdl64eS3;
    if (hdl64) args.insert(args.end(), {"--calibration-out", dir.file("cal.yaml")});
    MirageProcess emulate(args, dir.file("emulate.log"));
    ASSERT_EQ(emulate.wait(25s), 0) << emulate.output();
    EXPECT_NE(emulate.output().find("mirage emulate:"), std::string::npos) << emulate.output();
    std::string db_xml;
    if (hdl64) {
        db_xml = dir.file("db.xml");
        EXPECT_EQ(ros_calibration_to_pcl_db_xml(dir.file("cal.yaml"), db_xml), 64);
    }

    // The file itself: data packets at the model's rate (position packets ride along; PCL must
    // ignore them, it keeps only 1206-byte payloads).
    std::size_t data = 0, other = 0;
    const auto datagrams = pcap::read_udp(pcap_path);
    for (const auto& d : datagrams)
        (d.payload.size() == velodyne::kDataPacketSize ? data : other)++;
    const auto& desc = setup.descriptor();
    const double period_ns = static_cast<double>(desc.packet_period_ns(c.mode));
    const double expected_packets = kDurationS * 1e9 / period_ns;
    EXPECT_NEAR(static_cast<double>(data), expected_packets, 1.0);

    auto grabber = grabber_for(c.model, pcap_path, db_xml);
    SweepCollector sweeps;
    sweeps.attach(*grabber);
    grabber->start();
    // PCL replays at capture speed (0.6 s of packets): one sweep per azimuth wrap in the file.
    const std::size_t wraps = count_azimuth_wraps(datagrams);
    const bool all = sweeps.wait_for(wraps, 15s);
    grabber->stop();
    ASSERT_TRUE(all) << "PCL emitted " << sweeps.count() << " of " << wraps << " sweeps";
    EXPECT_EQ(sweeps.count(), wraps);

    const sensor::SensorModel preset = sensor::preset(c.sensor);
    const double extra = c.noise ? 5.0 * preset.noise.range_sigma_m : 0.0;
    const RoomChecker checker(room, setup, c.azimuth_tol_deg, extra);
    const std::string label =
        std::string(c.sensor) + (c.noise ? " pcap noise" : " pcap") + (dual ? " dual" : "");
    std::printf("[%s] %zu data packets (model %.1f), %zu other datagrams\n", label.c_str(), data,
                expected_packets, other);
    const SweepSummary s = expect_room_sweeps(sweeps.sweeps(), setup, checker, 4, label.c_str());
    if (c.noise) {
        // The noise is really there: some point is further off than the noiseless tolerance.
        EXPECT_GT(s.geometry.worst_m, 2.0 * preset.noise.range_sigma_m);
    }
}

TEST(PclPcap, vlp16_points_lie_on_room_planes_and_each_revolution_has_16_times_the_firings) {
    run_pcap_case({"vlp16", velodyne::Model::Vlp16, false, 0.016});
}

TEST(PclPcap, hdl32e_points_lie_on_room_planes_and_each_revolution_has_32_times_the_firings) {
    run_pcap_case({"hdl32e", velodyne::Model::Hdl32e, false, 0.006});
}

TEST(PclPcap, vlp16_with_range_noise_stays_within_five_sigma_of_the_planes) {
    run_pcap_case({"vlp16", velodyne::Model::Vlp16, true, 0.016});
}

TEST(PclPcap, hdl32e_with_range_noise_stays_within_five_sigma_of_the_planes) {
    run_pcap_case({"hdl32e", velodyne::Model::Hdl32e, true, 0.006});
}

// PCL reads HDL-64E corrections only from its db.xml: Mirage's ROS calibration YAML is converted
// (same angles), and PCL applies rot/vert corrections per laser (upper block 0–31, lower 32–63).
TEST(PclPcap, hdl64e_s3_with_converted_calibration_lies_on_room_planes_64_points_per_firing) {
    run_pcap_case({"hdl64e-s3", velodyne::Model::Hdl64eS3, false, 0.006});
}

// The room has one surface per ray, so a dual stream repeats each return in both blocks of a
// pair (§1.5). VLPGrabber (mode byte 0x39) adds the second return only when it differs: the same
// points per revolution as single return.
TEST(PclPcap, vlp16_dual_return_stream_gives_single_return_counts_in_vlp_grabber) {
    run_pcap_case({"vlp16", velodyne::Model::Vlp16, false, 0.016, velodyne::ReturnMode::Dual});
}

// HDLGrabber has no dual-return logic: both blocks of a pair decode as firings, so every point
// appears twice (a PCL limitation, asserted so a change is noticed).
TEST(PclPcap, hdl32e_dual_return_stream_doubles_every_point_in_hdl_grabber) {
    run_pcap_case({"hdl32e", velodyne::Model::Hdl32e, false, 0.006, velodyne::ReturnMode::Dual});
}

}  // namespace
}  // namespace mirage::test
