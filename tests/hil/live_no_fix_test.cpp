// SPDX-License-Identifier: Apache-2.0
// An INS without a fix (issue 22 item 7): a real lidar spins and sends packets before GPS lock,
// so `mirage live` and `mirage rig` stream packets without returns on the host's clock until the
// first full pose, instead of giving up; `--first-nav-timeout` keeps the old contract (send
// nothing, fail) as an option. A fix that comes later starts the returns, on the INS's clock.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <regex>
#include <thread>

#include "background_mirage.hpp"
#include "cli_run.hpp"
#include "live_yard.hpp"
#include "mirage/velodyne/position_packet.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

// NMEA from a receiver without a fix: GGA quality 0 and RMC status V with empty fields, 10 Hz.
class NoFixTalker {
  public:
    explicit NoFixTalker(int port) : port_(port), thread_([this] { run(); }) {}
    ~NoFixTalker() {
        stop_ = true;
        thread_.join();
    }
    int sent() const { return sent_.load(); }

  private:
    void run() {
        const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(static_cast<std::uint16_t>(port_));
        ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
        const std::string lines = "$GPGGA,,,,,,0,00,99.99,,,,,,*48\r\n$GPRMC,,V,,,,,,,,,,N*53\r\n";
        while (!stop_) {
            ::sendto(fd, lines.data(), lines.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
            ++sent_;
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        ::close(fd);
    }
    int port_;
    std::atomic<bool> stop_{false};
    std::atomic<int> sent_{0};
    std::thread thread_;
};

int udp_port_in(BackgroundMirage& m) {
    std::smatch g;
    const std::string l = m.wait_for(std::regex("udp port [0-9]+"));
    return std::regex_search(l, g, std::regex("udp port ([0-9]+)")) ? std::stoi(g[1]) : -1;
}

// Position packets: how many report PPS absent with a void $GPRMC, and how many PPS locked with
// a valid one.
struct PpsCount {
    std::size_t unlocked = 0, locked = 0, other = 0;
};
PpsCount pps_in(const std::vector<std::vector<std::uint8_t>>& packets) {
    PpsCount c;
    velodyne::DecodedPosition d;
    for (const auto& p : packets) {
        if (velodyne::decode_position(p, d) != velodyne::PositionStatus::Ok) continue;
        if (d.pps == 0 && d.rmc && !d.fix_valid)
            ++c.unlocked;
        else if (d.pps == 2 && d.rmc && d.fix_valid)
            ++c.locked;
        else
            ++c.other;
    }
    return c;
}

std::size_t returns_in(const std::vector<std::vector<std::uint8_t>>& packets, std::size_t& ok) {
    std::size_t n = 0;
    velodyne::DecodedPacket dp;
    ok = 0;
    for (const auto& p : packets) {
        if (p.size() != 1206 || velodyne::decode_data(p, nullptr, dp) != velodyne::DecodeStatus::Ok)
            continue;
        ++ok;
        for (const auto& f : dp.firing) n += f.distance_m > 0;
    }
    return n;
}

TEST(NoFix, an_ins_without_a_fix_streams_packets_without_returns) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    Collector rx, pos;
    BackgroundMirage live =
        start_mirage("live --scene " + tmp.file("yard.yaml") +
                     " --sensor vlp16 --no-status --duration 3 --nav-origin 45,9,100"
                     " --nav nmea:udp://127.0.0.1:0 --to 127.0.0.1 --data-port " +
                     std::to_string(rx.port()) + " --position-port " + std::to_string(pos.port()));
    const int port = udp_port_in(live);
    ASSERT_GT(port, 0) << live.output;
    int sent = 0;
    {
        NoFixTalker talker(port);
        live.wait_for(std::regex("before the first pose"));
        sent = talker.sent();
    }
    const int rc = live.finish();
    rx.stop();
    pos.stop();
    std::size_t ok = 0;
    const std::size_t returns = returns_in(rx.packets(), ok);
    const PpsCount pc = pps_in(pos.packets());
    std::printf(
        "[ no fix ] %d NMEA bursts without a fix; %zu packets received, %zu returns; "
        "position packets: %zu PPS absent + void RMC, %zu locked, %zu other\n%s",
        sent, ok, returns, pc.unlocked, pc.locked, pc.other, live.output.c_str());
    EXPECT_GT(pc.unlocked, 10u);  // 3 s of the model's position packets
    EXPECT_EQ(pc.locked + pc.other, 0u);
    ASSERT_EQ(rc, 0) << live.output;
    EXPECT_GT(ok, 1350u);  // 3 s less the 1 s wait for a pose, at 753.5 packets/s
    EXPECT_EQ(returns, 0u);
    EXPECT_NE(live.output.find("no full pose yet: streaming without returns"), std::string::npos);
    EXPECT_GT(sent, 20);
}

TEST(NoFix, first_nav_timeout_keeps_the_option_to_give_up) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    Collector rx;
    const RunResult r = run_mirage(
        "live --scene " + tmp.file("yard.yaml") +
        " --sensor vlp16 --position-port 0 --no-status --nav-origin 45,9,100"
        " --first-nav-timeout 1 --nav nmea:udp://127.0.0.1:0 --to 127.0.0.1 --data-port " +
        std::to_string(rx.port()));
    rx.stop();
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("no full pose"), std::string::npos) << r.output;
    EXPECT_TRUE(rx.packets().empty());
}

// A rig on DIS whose entity appears 2.5 s late: packets without returns first, then points on
// the yard placed with the truth at their own (INS) times.
TEST(NoFix, a_late_fix_starts_the_returns_on_the_ins_clock) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    write_trajectory(tmp.file("circle.csv"));
    const core::Trajectory truth = circle_truth(tmp.file("circle.csv"));
    Collector rx, pos;
    {
        std::ofstream(tmp.file("rig.yaml"))
            << "scene: yard.yaml\n"
               "navigation: {nav: 'dis:udp://127.0.0.1:0?entity=1.1.1', max_extrapolation_ms: "
               "150}\n"
               "duration: 5\n"
               "sensors:\n"
               "  - {name: roof, sensor: vlp16, to: 127.0.0.1, ports: {data: "
            << rx.port() << ", position: " << pos.port() << "}}\n";
    }
    BackgroundMirage rig = start_mirage("rig " + tmp.file("rig.yaml") + " --no-status");
    const int port = udp_port_in(rig);
    ASSERT_GT(port, 0) << rig.output;
    rig.wait_for(std::regex("no full pose yet"));
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    BackgroundMirage fake = start_mirage(
        "fake-ins --scene " + tmp.file("yard.yaml") + " --trajectory " + tmp.file("circle.csv") +
        " --protocol dis --duration 6 --to udp://127.0.0.1:" + std::to_string(port));
    const core::GpsTime t0 = parse_t0(fake.wait_for(std::regex("t0 gps:")));
    const int rig_rc = rig.finish(), fake_rc = fake.finish();
    rx.stop();
    pos.stop();
    ASSERT_EQ(rig_rc, 0) << rig.output;
    const PpsCount pc = pps_in(pos.packets());
    std::printf(
        "[ late fix ] position packets: %zu PPS absent + void RMC, then %zu locked, %zu "
        "other\n",
        pc.unlocked, pc.locked, pc.other);
    EXPECT_GT(pc.unlocked, 5u);
    EXPECT_GT(pc.locked, 5u);
    EXPECT_EQ(pc.other, 0u);
    ASSERT_EQ(fake_rc, 0) << fake.output;
    std::size_t ok = 0;
    (void)returns_in(rx.packets(), ok);
    const Stats st = check_points(rx.packets(), truth, t0);
    std::printf("[ late fix ] %zu packets, %zu points, median %.4f m, p99 %.4f m\n%s", ok,
                st.points, st.median, st.p99, rig.output.c_str());
    EXPECT_NE(rig.output.find("before the first pose"), std::string::npos);
    EXPECT_GT(ok, 2700u);  // 5 s less the 1 s wait, at 753.5 packets/s, less a margin
    EXPECT_GT(st.points, 100000u);
    EXPECT_LT(st.median, 0.02);
    EXPECT_LT(st.p99, 0.1);
}

}  // namespace
}  // namespace mirage::test
