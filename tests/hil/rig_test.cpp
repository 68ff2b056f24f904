// SPDX-License-Identifier: Apache-2.0
// `mirage rig` (issue 22 items 1–2): two VLP-16s on one platform in the walled yard, each on its
// own mount and ports, streamed by one process on one sensor clock to two loopback receivers.
// Every point, put in the world with platform pose ∘ that sensor's mount, lies on the yard; both
// streams carry the device's packet count and the same packet times. `--check` and the errors.
#include <gtest/gtest.h>

#include <fstream>
#include <initializer_list>
#include <regex>

#include "background_mirage.hpp"
#include "cli_run.hpp"
#include "live_yard.hpp"
#include "mirage/core/pose.hpp"
#include "mirage/las/las_reader.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

constexpr double kDeg = M_PI / 180;

std::string rig_text(std::uint16_t left_port, std::uint16_t rear_port) {
    return "scene: yard.yaml\n"
           "navigation: {trajectory: 'static:2,-3,1.8,0,0,30'}\n"
           "duration: 1\n"
           "sensors:\n"
           "  - name: left\n"
           "    sensor: vlp16\n"
           "    mount: {lever_arm: [1, 0.5, 0.3], boresight: [0, 0, 90]}\n"
           "    to: 127.0.0.1\n"
           "    ports: {data: " +
           std::to_string(left_port) +
           "}\n"
           "  - name: rear\n"
           "    sensor: vlp16\n"
           "    mount: {lever_arm: [-1, 0, 0.5], boresight: [0, 10, 180]}\n"
           "    to: 127.0.0.1\n"
           "    ports: {data: " +
           std::to_string(rear_port) + "}\n";
}

struct SensorCheck {
    std::size_t packets = 0, points = 0;
    double median = 0, p99 = 0;
    std::uint32_t first_timestamp_us = 0;
};

// Points of one stream against the yard with the sensor's world pose.
SensorCheck check(const std::vector<std::vector<std::uint8_t>>& packets, const core::Pose& pose) {
    SensorCheck c;
    std::vector<double> err;
    velodyne::DecodedPacket dp;
    for (const auto& p : packets) {
        if (p.size() != 1206 || velodyne::decode_data(p, nullptr, dp) != velodyne::DecodeStatus::Ok)
            continue;
        if (c.packets++ == 0) c.first_timestamp_us = dp.timestamp_us;
        for (const auto& f : dp.firing)
            if (f.distance_m > 0) err.push_back(distance_to_yard(pose.apply({f.x, f.y, f.z})));
    }
    c.points = err.size();
    if (!err.empty()) {
        std::sort(err.begin(), err.end());
        c.median = err[err.size() / 2];
        c.p99 = err[err.size() * 99 / 100];
    }
    return c;
}

core::Pose mount(const Eigen::Vector3d& lever, double roll, double pitch, double yaw) {
    return {lever, core::quaternion_from_rpy(roll * kDeg, pitch * kDeg, yaw * kDeg)};
}

TEST(Rig, two_mounted_sensors_stream_on_one_clock_onto_the_yard) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    Collector left, rear;
    {
        std::string text = rig_text(left.port(), rear.port());
        text.insert(text.find("  - name: rear"), "    las: left.las\n");  // its points too
        std::ofstream(tmp.file("rig.yaml")) << text;
    }
    const RunResult r = run_mirage("rig " + tmp.file("rig.yaml") + " --no-status");
    left.stop();
    rear.stop();
    ASSERT_EQ(r.exit_code, 0) << r.output;
    // The left sensor's LAS: every point it sent, georeferenced, on the yard.
    const las::LasFile lf = las::LasFile::read(tmp.file("left.las"));
    std::vector<double> las_err;
    for (const auto& p : lf.points())
        las_err.push_back(distance_to_yard({p.x - 500000, p.y - 5000000, p.z}));
    std::sort(las_err.begin(), las_err.end());
    ASSERT_FALSE(las_err.empty());
    std::printf("[ rig las ] left.las: %zu points, median %.4f m, p99 %.4f m off the yard\n",
                las_err.size(), las_err[las_err.size() / 2], las_err[las_err.size() * 99 / 100]);
    EXPECT_LT(las_err[las_err.size() / 2], 0.02);
    EXPECT_LT(las_err[las_err.size() * 99 / 100], 0.1);
    const core::Pose platform{{2, -3, 1.8}, core::quaternion_from_rpy(0, 0, 30 * kDeg)};
    const SensorCheck l = check(left.packets(), platform * mount({1, 0.5, 0.3}, 0, 0, 90));
    const SensorCheck b = check(rear.packets(), platform * mount({-1, 0, 0.5}, 0, 10, 180));
    std::printf(
        "[ rig ] left: %zu packets, %zu points, median %.4f m, p99 %.4f m; rear: %zu packets, "
        "%zu points, median %.4f m, p99 %.4f m; first packet times %u / %u µs past the hour\n%s",
        l.packets, l.points, l.median, l.p99, b.packets, b.points, b.median, b.p99,
        l.first_timestamp_us, b.first_timestamp_us, r.output.c_str());
    // 1 s of VLP-16: 753.5 data packets (the last may fall either side of the end).
    for (const SensorCheck* c : {&l, &b}) {
        EXPECT_GE(c->packets, 753u);
        EXPECT_LE(c->packets, 754u);
        EXPECT_GT(c->points, 200'000u);
        EXPECT_LT(c->median, 0.02);  // the sensor's range noise is on (σ a few cm)
        EXPECT_LT(c->p99, 0.1);
    }
    EXPECT_EQ(l.first_timestamp_us, b.first_timestamp_us);  // one sensor clock
    EXPECT_GE(las_err.size(), l.points);  // a packet's slots hold the strongest of a pulse's
    EXPECT_NE(r.output.find("left: 7"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("failed sends 0"), std::string::npos) << r.output;
    // Swapping the mounts puts the points off the walls: the mounts are each sensor's own.
    EXPECT_GT(check(left.packets(), platform * mount({-1, 0, 0.5}, 0, 10, 180)).p99, 0.5);
}

// A live source drives the rig: `mirage fake-ins --protocol dis` sends the car circling the
// yard to the rig's UDP port; both sensors' points, placed with the truth pose at their times
// composed with each sensor's mount, lie on the yard.
TEST(Rig, a_dis_entity_drives_two_mounted_sensors_onto_the_yard) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    write_trajectory(tmp.file("circle.csv"));
    const core::Trajectory truth = circle_truth(tmp.file("circle.csv"));
    Collector left, rear;
    std::string text = rig_text(left.port(), rear.port());
    const std::string static_nav = "navigation: {trajectory: 'static:2,-3,1.8,0,0,30'}";
    text.replace(text.find(static_nav), static_nav.size(),
                 "navigation: {nav: 'dis:udp://127.0.0.1:0?entity=1.1.1', "
                 "max_extrapolation_ms: 150, first_nav_timeout: 15}");
    text.replace(text.find("duration: 1"), 11, "duration: 3");
    { std::ofstream(tmp.file("rig.yaml")) << text; }
    BackgroundMirage rig = start_mirage("rig " + tmp.file("rig.yaml") + " --no-status");
    std::smatch m;
    const std::string l = rig.wait_for(std::regex("udp port [0-9]+"));
    ASSERT_TRUE(std::regex_search(l, m, std::regex("udp port ([0-9]+)"))) << rig.output;
    BackgroundMirage fake = start_mirage(
        "fake-ins --scene " + tmp.file("yard.yaml") + " --trajectory " + tmp.file("circle.csv") +
        " --protocol dis --duration 6 --to udp://127.0.0.1:" + m[1].str());
    const core::GpsTime t0 = parse_t0(fake.wait_for(std::regex("t0 gps:")));
    const int rig_rc = rig.finish(), fake_rc = fake.finish();
    left.stop();
    rear.stop();
    ASSERT_EQ(rig_rc, 0) << rig.output;
    ASSERT_EQ(fake_rc, 0) << fake.output;
    const Stats a = check_points(left.packets(), truth, t0, mount({1, 0.5, 0.3}, 0, 0, 90));
    const Stats b = check_points(rear.packets(), truth, t0, mount({-1, 0, 0.5}, 0, 10, 180));
    std::printf(
        "[ rig dis ] left: %zu packets, %zu points, median %.4f m, p99 %.4f m; rear: %zu "
        "packets, %zu points, median %.4f m, p99 %.4f m\n%s",
        a.packets, a.points, a.median, a.p99, b.packets, b.points, b.median, b.p99,
        rig.output.c_str());
    for (const Stats* st : {&a, &b}) {
        EXPECT_GT(st->packets, 2100u);  // 3 s of 753.5 packets/s
        EXPECT_LT(st->median, 0.02);    // range noise on
        EXPECT_LT(st->p99, 0.1);
    }
    EXPECT_NE(rig.output.find("dis entity 1.1.1"), std::string::npos) << rig.output;
    // Each sensor's line: no stale window.
    for (const char* name : {"  left: ", "  rear: "}) {
        const auto at = rig.output.rfind(name);
        ASSERT_NE(at, std::string::npos) << rig.output;
        const std::string line = rig.output.substr(at, rig.output.find('\n', at) - at);
        EXPECT_NE(line.find("stale windows 0 in 0 periods"), std::string::npos) << line;
    }
    // One sensor clock: both streams' first packets carry the same time.
    velodyne::DecodedPacket first_left, first_rear;
    ASSERT_FALSE(left.packets().empty());
    ASSERT_FALSE(rear.packets().empty());
    ASSERT_EQ(velodyne::decode_data(left.packets().front(), nullptr, first_left),
              velodyne::DecodeStatus::Ok);
    ASSERT_EQ(velodyne::decode_data(rear.packets().front(), nullptr, first_rear),
              velodyne::DecodeStatus::Ok);
    EXPECT_EQ(first_left.timestamp_us, first_rear.timestamp_us);
}

TEST(Rig, check_prints_the_effective_configuration_and_sends_nothing) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    Collector left;
    { std::ofstream(tmp.file("rig.yaml")) << rig_text(left.port(), 2399); }
    const RunResult r = run_mirage("rig " + tmp.file("rig.yaml") + " --check");
    left.stop();
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(left.packets().empty());
    EXPECT_NE(r.output.find("left: velodyne vlp16 (return mode strongest), 753.5 data packets/s; "
                            "lever arm [1, 0.5, 0.3] m, boresight [0, 0, 90] deg"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("-> 127.0.0.1: data 2399"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("2 sensors, 1507.0 data packets/s in all"), std::string::npos)
        << r.output;
}

// The rig text with `from` replaced by `to`, checked: exit 2 and every `want` in the message.
void expect_refused(const TempDir& tmp, const std::string& name, const std::string& from,
                    const std::string& to, std::initializer_list<const char*> want) {
    std::string text = rig_text(2368, 2369);
    const auto at = text.rfind(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    { std::ofstream(tmp.file(name)) << text; }
    const RunResult r = run_mirage("rig " + tmp.file(name) + " --check");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    for (const char* w : want)
        EXPECT_NE(r.output.find(w), std::string::npos) << w << ": " << r.output;
}

TEST(Rig, errors_name_the_file_the_sensor_and_the_line_and_exit_2) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    expect_refused(tmp, "rig.yaml", "sensor: vlp16", "sensor: vlp17",
                   {"sensors[1] ('rear', line 10)", "vlp17"});
    // Settings checked before anything runs, naming the key.
    expect_refused(tmp, "start.yaml", "duration: 1", "duration: 1\nstart: yesterday",
                   {"start.yaml': start: "});
    expect_refused(tmp, "nav.yaml", "navigation: {trajectory: 'static:2,-3,1.8,0,0,30'}",
                   "navigation: {nav: 'dis:udp://:0?entity=1.2'}",
                   {"navigation.nav: ", "entity='1.2'"});
    const RunResult m = run_mirage("rig " + tmp.file("missing.yaml"));
    EXPECT_EQ(m.exit_code, 2) << m.output;
    EXPECT_NE(m.output.find("cannot open"), std::string::npos) << m.output;
}

// A recorded navigation log as the rig's navigation (re-simulated, on the log's own times):
// `mirage live --nav-record` keeps what fake-ins sent over UDP; the rig then replays it and every
// point, placed with the truth at its time, lies on the yard.
TEST(Rig, a_recorded_nav_log_drives_the_rig) {
    TempDir tmp;
    { std::ofstream(tmp.file("yard.yaml")) << kScene; }
    write_trajectory(tmp.file("circle.csv"));
    const core::Trajectory truth = circle_truth(tmp.file("circle.csv"));
    BackgroundMirage live = start_mirage(
        "live --scene " + tmp.file("yard.yaml") +
        " --sensor vlp16 --position-port 0 --no-status --duration 3 --first-nav-timeout 15"
        " --nav nmea:udp://127.0.0.1:0 --nav-record " +
        tmp.file("drive.nmea"));
    std::smatch m;
    const std::string l = live.wait_for(std::regex("udp port [0-9]+"));
    ASSERT_TRUE(std::regex_search(l, m, std::regex("udp port ([0-9]+)"))) << live.output;
    BackgroundMirage fake = start_mirage(
        "fake-ins --scene " + tmp.file("yard.yaml") + " --trajectory " + tmp.file("circle.csv") +
        " --protocol nmea --duration 5 --to udp://127.0.0.1:" + m[1].str());
    const core::GpsTime t0 = parse_t0(fake.wait_for(std::regex("t0 gps:")));
    ASSERT_EQ(live.finish(), 0) << live.output;
    (void)fake.finish();
    Collector rx;
    {
        std::ofstream(tmp.file("rig.yaml"))
            << "scene: yard.yaml\nnavigation: {nav_log: drive.nmea, protocol: nmea}\n"
               "duration: 1.5\nsensors:\n  - {name: roof, sensor: vlp16, to: 127.0.0.1, ports: "
               "{data: "
            << rx.port() << "}}\n";
    }
    const RunResult r = run_mirage("rig " + tmp.file("rig.yaml") + " --no-status");
    rx.stop();
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Stats st = check_points(rx.packets(), truth, t0);
    std::printf("[ rig nav log ] %zu packets, %zu points, median %.4f m, p99 %.4f m\n%s",
                st.packets, st.points, st.median, st.p99, r.output.c_str());
    EXPECT_GT(st.packets, 1000u);  // 1.5 s at 753.5 packets/s
    EXPECT_LT(st.median, 0.05);
    EXPECT_NE(r.output.find("nmea log"), std::string::npos);
}

}  // namespace
}  // namespace mirage::test
