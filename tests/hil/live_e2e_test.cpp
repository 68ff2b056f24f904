// SPDX-License-Identifier: Apache-2.0
// The loopback HIL harness end to end, for each navigation protocol: `mirage fake-ins` follows a
// scripted trajectory in real time -> pty / UDP / slcan pty / in-memory CAN -> `mirage live` ->
// Velodyne UDP -> our decoder. Every decoded point, put in the world with the TRUTH pose at its
// own timestamp, must lie on the scene's walls or ground.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <thread>

#include "background_mirage.hpp"
#include "cli_run.hpp"
#include "mirage/core/georef.hpp"
#include "mirage/core/time.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/udp/udp_receiver.hpp"
#include "mirage/velodyne/data_packet.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

// A 80 x 80 m walled yard in UTM 32N: ground z = 0, inner wall faces at x, y = ±40.
constexpr const char* kScene = R"(georef: {epsg: 32632, anchor: [500000, 5000000, 0]}
materials:
  ground: {reflectance: 0.3, classification: 2}
  wall: {reflectance: 0.5, classification: 6}
objects:
  - {type: plane, material: ground, size: [120, 120]}
  - {type: box, material: wall, size: [82, 1, 20], transform: {translate: [0, 40.5, 10]}}
  - {type: box, material: wall, size: [82, 1, 20], transform: {translate: [0, -40.5, 10]}}
  - {type: box, material: wall, size: [1, 82, 20], transform: {translate: [40.5, 0, 10]}}
  - {type: box, material: wall, size: [1, 82, 20], transform: {translate: [-40.5, 0, 10]}}
)";

double distance_to_yard(const Eigen::Vector3d& p) {
    return std::min({std::abs(p.z()), std::abs(p.x() - 40), std::abs(p.x() + 40),
                     std::abs(p.y() - 40), std::abs(p.y() + 40)});
}

// A car circling at 6 m/s on a 15 m radius (yaw rate 0.4 rad/s), 40 s of samples every 50 ms.
void write_trajectory(const std::string& path) {
    std::ofstream f(path);
    f << "time,x,y,z,roll,pitch,yaw\n";
    for (int i = 0; i <= 800; ++i) {
        const double t = 0.05 * i, a = 0.4 * t;
        f << t << ',' << 15 * std::cos(a) << ',' << 15 * std::sin(a) << ",1.8,0,0,"
          << (a + M_PI / 2) * 180 / M_PI << '\n';
    }
}

core::GpsTime parse_t0(const std::string& line) {
    std::smatch m;
    const std::regex re("t0 gps:([0-9]+\\.[0-9]+)");
    if (!std::regex_search(line, m, re)) return {};
    return core::GpsTime(*core::parse_decimal_seconds(m[1].str()));
}

struct Received {
    std::vector<std::vector<std::uint8_t>> packets;
};

// Collects datagrams on a thread until `stop`.
class Collector {
  public:
    Collector() : thread_([this] { run(); }) {}
    ~Collector() { stop(); }
    void stop() {
        stop_ = true;
        if (thread_.joinable()) thread_.join();
    }
    std::uint16_t port() const { return rx_.port(); }
    const std::vector<std::vector<std::uint8_t>>& packets() const { return packets_; }

  private:
    void run() {
        udp::ReceivedDatagram d;
        while (!stop_)
            if (rx_.receive(d, std::chrono::milliseconds(50))) packets_.push_back(d.payload);
    }
    udp::UdpReceiver rx_;
    std::atomic<bool> stop_{false};
    std::vector<std::vector<std::uint8_t>> packets_;
    std::thread thread_;
};

struct Stats {
    std::size_t points = 0, packets = 0, bad_packets = 0;
    double median = 0, p99 = 0, max = 0, rms = 0;
};

Stats check_points(const std::vector<std::vector<std::uint8_t>>& packets,
                   const core::Trajectory& truth, core::GpsTime t0) {
    Stats st;
    std::vector<double> err;
    // Velodyne time is µs past the UTC hour: take the hour from t0 (a run lasts seconds).
    const std::int64_t t0_unix = core::unix_ns_from_gps(t0);
    const std::int64_t hour_ns = 3'600'000'000'000;
    velodyne::DecodedPacket dp;
    for (const auto& p : packets) {
        if (p.size() != 1206) continue;
        if (velodyne::decode_data(p, nullptr, dp) != velodyne::DecodeStatus::Ok) {
            ++st.bad_packets;
            continue;
        }
        ++st.packets;
        std::int64_t hour = t0_unix / hour_ns * hour_ns;
        std::int64_t unix_t = hour + std::int64_t(dp.timestamp_us) * 1000;
        if (unix_t < t0_unix - hour_ns / 2) unix_t += hour_ns;  // the hour rolled during the run
        for (const auto& f : dp.firing) {
            if (f.distance_m <= 0) continue;
            const core::GpsTime t = core::gps_from_unix_ns(unix_t + f.time_offset_ns);
            const core::Pose pose = truth.at(truth.begin() + (t - t0));
            err.push_back(distance_to_yard(pose.apply(Eigen::Vector3d(f.x, f.y, f.z))));
        }
    }
    st.points = err.size();
    if (err.empty()) return st;
    std::sort(err.begin(), err.end());
    st.median = err[err.size() / 2];
    st.p99 = err[err.size() * 99 / 100];
    st.max = err.back();
    double s2 = 0;
    for (double e : err) s2 += e * e;
    st.rms = std::sqrt(s2 / double(err.size()));
    return st;
}

// The clean runs allow 150 ms of extrapolation, so a scheduling hiccup of a loaded CI machine
// does not read as stale navigation; the fault run keeps the default 50 ms.
const char* kLiveCommon =
    " --sensor vlp16 --sub-rays 1 --no-noise --position-port 0 --duration 3 --no-status"
    " --first-nav-timeout 15 --to 127.0.0.1 --data-port ";

struct Case {
    std::string protocol;
    std::string fake_to;          // `mirage fake-ins --to` (with LINK for ptys)
    std::string nav;              // `mirage live --nav`
    double tolerance_p99;         // m: the protocol's resolution at ~55 m range
    std::string fake_extra = {};  // more `mirage fake-ins` options (faults)
    std::string live_extra = " --max-extrapolation-ms 150";
};

// "<label> <number>" from the live summary.
std::uint64_t figure(const std::string& out, const std::string& label) {
    std::smatch m;
    if (!std::regex_search(out, m, std::regex(label + " ([0-9]+)"))) return ~0ull;
    return std::stoull(m[1].str());
}

std::string run_case(const Case& c) {
    TempDir tmp;
    const std::string scene = tmp.file("yard.yaml"), traj = tmp.file("circle.csv");
    { std::ofstream(scene) << kScene; }
    write_trajectory(traj);
    const core::Trajectory truth = core::load_trajectory_csv(
        traj, core::Georef::projected(32632, {500000, 5000000, 0}), core::Interpolation::Cubic);
    Collector rx;
    const std::string link = tmp.file("ins");
    auto subst = [&](std::string s) {
        const auto at = s.find("LINK");
        if (at != std::string::npos) s.replace(at, 4, link);
        return s;
    };
    core::GpsTime t0{};
    int live_rc = -1, fake_rc = 0;
    std::string live_out, fake_out;
    if (c.fake_to.empty()) {  // in-process fake INS (memory bus)
        const auto r = run_mirage("live --scene " + scene + " --nav " + c.nav + " --fake-ins " +
                                  traj + kLiveCommon + std::to_string(rx.port()) + c.live_extra);
        live_rc = r.exit_code;
        live_out = r.output;
        t0 = parse_t0(live_out);
    } else if (c.fake_to == "udp") {  // live binds first and tells its port
        BackgroundMirage live =
            start_mirage("live --scene " + scene + " --nav " + c.nav + kLiveCommon +
                         std::to_string(rx.port()) + c.live_extra);
        const std::string l = live.wait_for(std::regex("udp port [0-9]+"));
        std::smatch m;
        EXPECT_TRUE(std::regex_search(l, m, std::regex("udp port ([0-9]+)"))) << live.output;
        if (m.empty()) return {};
        BackgroundMirage fake =
            start_mirage("fake-ins --scene " + scene + " --trajectory " + traj + " --protocol " +
                         c.protocol + " --duration 6 --to udp://127.0.0.1:" + m[1].str());
        t0 = parse_t0(fake.wait_for(std::regex("t0 gps:")));
        live_rc = live.finish();
        live_out = live.output;
        fake_rc = fake.finish();
        fake_out = fake.output;
    } else {  // fake INS first: it creates the pty the live command opens
        BackgroundMirage fake = start_mirage("fake-ins --scene " + scene + " --trajectory " + traj +
                                             " --protocol " + c.protocol + " --duration 6 --to " +
                                             subst(c.fake_to) + " " + c.fake_extra);
        t0 = parse_t0(fake.wait_for(std::regex("t0 gps:")));
        const auto r = run_mirage("live --scene " + scene + " --nav " + subst(c.nav) + kLiveCommon +
                                  std::to_string(rx.port()) + c.live_extra);
        live_rc = r.exit_code;
        live_out = r.output;
        fake_rc = fake.finish();
        fake_out = fake.output;
    }
    rx.stop();
    EXPECT_EQ(live_rc, 0) << live_out;
    EXPECT_EQ(fake_rc, 0) << fake_out;
    EXPECT_NE(t0.time_since_epoch().count(), 0) << live_out << fake_out;
    if (live_rc != 0 || fake_rc != 0 || t0.time_since_epoch().count() == 0) return {};
    const Stats st = check_points(rx.packets(), truth, t0);
    std::printf(
        "[ %s ] %zu packets, %zu points: distance to the yard median %.4f m, p99 %.4f m, "
        "max %.4f m, RMS %.4f m\n%s",
        c.protocol.c_str(), st.packets, st.points, st.median, st.p99, st.max, st.rms,
        live_out.c_str());
    EXPECT_EQ(st.bad_packets, 0u);
    // 3 s of VLP-16 data: 754 packets/s (a few at the ends may fall outside the run).
    EXPECT_GT(st.packets, 2100u);
    EXPECT_GT(st.points, 200'000u);
    EXPECT_LT(st.median, 0.01);
    EXPECT_LT(st.p99, c.tolerance_p99);
    if (c.fake_extra.empty()) {
        EXPECT_NE(live_out.find("stale windows 0 in 0 periods"), std::string::npos) << live_out;
    }
    return live_out + fake_out;
}

// Resolutions: NMEA PASHR heading 0.01° (1 cm at 57 m), NovAtel/NCOM near-exact, OxTS CAN
// 0.01° heading and 1e-7° position, SBG CAN 1e-4 rad attitude (6 mm at 57 m).
TEST(LiveE2E, nmea_over_a_pty) { (void)run_case({"nmea", "pty:LINK", "nmea:LINK", 0.03}); }
TEST(LiveE2E, novatel_over_a_pty) { (void)run_case({"novatel", "pty:LINK", "novatel:LINK", 0.02}); }
TEST(LiveE2E, ncom_over_udp) { (void)run_case({"ncom", "udp", "ncom:udp://127.0.0.1:0", 0.02}); }
TEST(LiveE2E, oxts_can_over_slcan_on_a_pty) {
    (void)run_case({"oxts-can", "slcan-pty:LINK", "oxts-can:slcan:LINK", 0.04});
}
TEST(LiveE2E, sbg_can_on_an_in_memory_bus) {
    (void)run_case({"sbg-can", "", "sbg-can:memory:e2e", 0.04});
}

// Faults from the fake INS (times after its start; live runs from ~0.6 s to ~3.6 s): a 300 ms
// silence, a 100 m position jump, an epoch stamped 1 s back, a NaN latitude and every 50th message
// corrupted. Live must go stale once (after its 50 ms extrapolation horizon) and resume, reject
// and count every bad message, and never apply one: the points stay on the geometry.
TEST(LiveE2E, faults_are_rejected_counted_and_never_applied) {
    const std::string out =
        run_case({"nmea", "pty:LINK", "nmea:LINK", 0.03,
                  "--silence 2.0,0.3 --jump-at 2.6 --backwards-at 2.8 --nan-at 3.0 "
                  "--corrupt-every 50",
                  ""});
    ASSERT_FALSE(out.empty());
    EXPECT_NE(out.find("faults: 30 epochs silenced, 1 jumps, 1 backwards, 1 NaN"),
              std::string::npos)
        << out;
    // 300 ms of silence − 50 ms of extrapolation ≈ 250 ms = 188 windows of 1.327 ms (± a message);
    // a loaded machine may add a short stale period of its own, never fewer windows.
    std::smatch m;
    ASSERT_TRUE(
        std::regex_search(out, m, std::regex("stale windows ([0-9]+) in ([0-9]+) periods")));
    const std::uint64_t stale = std::stoull(m[1].str()), periods = std::stoull(m[2].str());
    EXPECT_GE(periods, 1u) << out;
    EXPECT_GT(stale, 170u) << out;
    EXPECT_LT(stale, 170u + 200u * (periods - 1) + 45u) << out;
    EXPECT_GE(figure(out, "jumps"), 1u) << out;
    EXPECT_GE(figure(out, "time backwards"), 2u) << out;  // GGA and PASHR of that epoch
    EXPECT_GE(figure(out, "bad checksum"), 4u) << out;    // ≥ 4 of the corrupted epochs seen
    EXPECT_GE(figure(out, "invalid"), 1u) << out;         // the NaN latitude
}

}  // namespace
}  // namespace mirage::test
