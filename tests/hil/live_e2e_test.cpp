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
#include "live_yard.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

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

// The stale windows' span in ms: windows × the live loop's window (its "N pulses per window"
// over the VLP-16's 16 pulses per 55.296 µs firing cycle).
double stale_ms(const std::string& out, std::uint64_t windows) {
    std::smatch m;
    if (!std::regex_search(out, m, std::regex("([0-9]+) pulses per window"))) return -1.0;
    return double(windows) * std::stod(m[1].str()) / 16.0 * 0.055296;
}

std::string run_case(const Case& c) {
    TempDir tmp;
    const std::string scene = tmp.file("yard.yaml"), traj = tmp.file("circle.csv");
    { std::ofstream(scene) << kScene; }
    write_trajectory(traj);
    const core::Trajectory truth = circle_truth(traj);
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
        BackgroundMirage fake = start_mirage(
            "fake-ins --scene " + scene + " --trajectory " + traj + " --protocol " + c.protocol +
            " --duration 6 --to udp://127.0.0.1:" + m[1].str() + " " + c.fake_extra);
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
// DIS: the fake INS sends an Entity State PDU (RPB) per epoch; live dead-reckons between them.
TEST(LiveE2E, dis_over_udp) {
    const std::string out =
        run_case({"dis", "udp", "'dis:udp://127.0.0.1:0?exercise=1&entity=1.1.1'", 0.02});
    EXPECT_NE(out.find("dis entity 1.1.1"), std::string::npos) << out;
}
TEST(LiveE2E, oxts_can_over_slcan_on_a_pty) {
    (void)run_case({"oxts-can", "slcan-pty:LINK", "oxts-can:slcan:LINK", 0.04});
}
TEST(LiveE2E, sbg_can_on_an_in_memory_bus) {
    (void)run_case({"sbg-can", "", "sbg-can:memory:e2e", 0.04});
}

// The live loop renders a packet in windows that divide it (docs/live-navigation.md §1): the
// fewest spanning at most twice the pipeline delay, more where the packet's firing groups do
// not divide so. A window that straddled two packets would hold the first one back.
TEST(LiveE2E, windows_divide_a_packet_and_span_at_most_twice_the_delay) {
    TempDir tmp;
    const std::string scene = tmp.file("yard.yaml"), traj = tmp.file("circle.csv");
    { std::ofstream(scene) << kScene; }
    write_trajectory(traj);
    struct Want {
        std::string sensor, delay_us;
        int pulses;
    };
    // VLP-16: 384 pulses (24 groups of 16) per 1.327 ms packet; OS1-64 1024×10: 1 024 (16
    // columns of 64) per 1.5625 ms; at 300 µs it needs 3 windows, which 16 columns do not
    // divide: 4.
    for (const Want& w : {Want{"vlp16", "250", 128}, Want{"vlp16", "1000", 384},
                          Want{"vlp16", "100", 48}, Want{"os1-64-1024x10", "300", 256}}) {
        const auto r = run_mirage("live --scene " + scene + " --nav sbg-can:memory:w --fake-ins " +
                                  traj + " --sensor " + w.sensor + " --pipeline-delay-us " +
                                  w.delay_us + " --duration 0.2 --no-status");
        std::smatch m;
        ASSERT_TRUE(std::regex_search(r.output, m, std::regex("([0-9]+) pulses per window")))
            << r.output;
        EXPECT_EQ(std::stoi(m[1].str()), w.pulses) << w.sensor << " at " << w.delay_us << " µs";
    }
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
    // 300 ms of silence − 50 ms of extrapolation ≈ 250 ms stale (± a message); a loaded machine
    // may add a short stale period of its own, never less.
    std::smatch m;
    ASSERT_TRUE(
        std::regex_search(out, m, std::regex("stale windows ([0-9]+) in ([0-9]+) periods")));
    const double stale = stale_ms(out, std::stoull(m[1].str()));
    const auto periods = double(std::stoull(m[2].str()));
    EXPECT_GE(periods, 1.0) << out;
    EXPECT_GT(stale, 225.0) << out;
    EXPECT_LT(stale, 285.0 + 265.0 * (periods - 1.0)) << out;
    EXPECT_GE(figure(out, "jumps"), 1u) << out;
    EXPECT_GE(figure(out, "time backwards"), 2u) << out;  // GGA and PASHR of that epoch
    EXPECT_GE(figure(out, "bad checksum"), 4u) << out;    // ≥ 4 of the corrupted epochs seen
    EXPECT_GE(figure(out, "invalid"), 1u) << out;         // the NaN latitude
}

// DIS heartbeat timeout: the sender falls silent from 0.8 s to 2.4 s; dead reckoning carries the
// car for the 1 s timeout (exactly: RPB on a steady turn), then no samples, the poses go stale
// after the 150 ms of extrapolation, and the next PDU resumes.
TEST(LiveE2E, dis_silence_outlasts_the_timeout_and_goes_stale) {
    const std::string out =
        run_case({"dis", "udp", "'dis:udp://127.0.0.1:0?entity=1.1.1&timeout=1'", 0.02,
                  "--silence 0.8,1.6"});
    ASSERT_FALSE(out.empty());
    EXPECT_NE(out.find("timeouts 1,"), std::string::npos) << out;
    std::smatch m;
    ASSERT_TRUE(
        std::regex_search(out, m, std::regex("stale windows ([0-9]+) in ([0-9]+) periods")));
    // 1.6 s − 1 s − 0.15 s ≈ 450 ms stale; the start of live is not aligned with the sender's
    // first epoch to better than ~0.1 s.
    EXPECT_GE(std::stoull(m[2].str()), 1u) << out;
    EXPECT_GT(stale_ms(out, std::stoull(m[1].str())), 265.0) << out;
    EXPECT_LT(stale_ms(out, std::stoull(m[1].str())), 663.0) << out;
}

}  // namespace
}  // namespace mirage::test
