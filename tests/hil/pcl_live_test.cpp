// SPDX-License-Identifier: Apache-2.0
// PCL 1.13's grabbers listen on a loopback UDP port while `mirage emulate --realtime` streams a
// closed room to it: the same geometry and per-revolution checks as the pcap path, live.
#include <gtest/gtest.h>
#include <pcl/io/hdl_grabber.h>
#include <pcl/io/vlp_grabber.h>

#include <chrono>
#include <memory>

#include "mirage/sensor/sensor.hpp"
#include "pcl_harness.hpp"
#include "sweep_checks.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

using namespace std::chrono_literals;

constexpr std::size_t kFullRevolutions = 5;

void run_live_case(const char* sensor_name, velodyne::Model model, double azimuth_tol_deg) {
    TempDir dir;
    const Room room;
    room.write(dir.file("room.yaml"));
    SensorSetup setup;
    setup.model = model;

    const std::uint16_t port = pick_free_udp_port();
    const auto loopback = boost::asio::ip::address::from_string("127.0.0.1");
    std::unique_ptr<pcl::HDLGrabber> grabber;
    if (model == velodyne::Model::Vlp16)
        grabber = std::make_unique<pcl::VLPGrabber>(loopback, port);
    else
        grabber = std::make_unique<pcl::HDLGrabber>(loopback, port);
    SweepCollector sweeps;
    sweeps.attach(*grabber);
    grabber->start();  // binds the socket before returning

    auto args = emulate_args(setup, sensor_name, dir.file("room.yaml"), false);
    args.insert(args.end(), {"--to", "127.0.0.1", "--data-port", std::to_string(port),
                             "--position-port", "0", "--duration", "1.5", "--realtime"});
    MirageProcess emulate(args, dir.file("emulate.log"));

    // PCL's first sweep starts mid-turn: wait for it plus the full ones.
    const bool enough = sweeps.wait_for(kFullRevolutions + 1, 15s);
    const int code = emulate.wait(20s);
    const bool stopped = stop_udp_grabber(*grabber, port, 5000ms);
    if (!stopped) (void)grabber.release();  // its reader thread is stuck; never destroy it
    ASSERT_TRUE(stopped) << "PCL grabber did not stop";
    ASSERT_EQ(code, 0) << emulate.output();
    ASSERT_TRUE(enough) << "only " << sweeps.count() << " sweeps; emulate said:\n"
                        << emulate.output();

    const RoomChecker checker(room, setup, azimuth_tol_deg, 0.0);
    const std::string label = std::string(sensor_name) + " live udp";
    expect_room_sweeps(sweeps.sweeps(), setup, checker, kFullRevolutions, label.c_str(),
                       PacketLoss::WholePacketsAllowed);
}

TEST(PclLive, vlp16_grabber_on_loopback_sees_five_full_revolutions_on_the_room_planes) {
    run_live_case("vlp16", velodyne::Model::Vlp16, 0.016);
}

TEST(PclLive, hdl32e_grabber_on_loopback_sees_five_full_revolutions_on_the_room_planes) {
    run_live_case("hdl32e", velodyne::Model::Hdl32e, 0.006);
}

}  // namespace
}  // namespace mirage::test
