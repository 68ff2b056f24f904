// SPDX-License-Identifier: Apache-2.0
// One navigation path: the SAME faulty NMEA log (a bad checksum, a NaN latitude, an epoch
// stamped in the past, a 100 m jump, heading-only PTNL,AVR and HDT sentences) goes
//  - live: `mirage fake-ins --log` replays it over UDP into `mirage live --pose-log`;
//  - re-simulation: `mirage render --nav-log` (and navproto::nav_log_tracks, which it uses);
//  - `mirage fake-ins --log`'s own report of what live would refuse;
// and all three must accept the same track updates and print the same counters line.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>

#include "background_mirage.hpp"
#include "cli_run.hpp"
#include "mirage/core/georef.hpp"
#include "mirage/core/time.hpp"
#include "mirage/navpose/nav_frame.hpp"
#include "mirage/navproto/nav_log.hpp"
#include "mirage/nmea/nmea_encoder.hpp"
#include "mirage/nmea/sentence.hpp"
#include "test_paths.hpp"
#include "utm_ground_scene.hpp"

namespace mirage::test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr const char* kScene = kUtmGroundScene;
const core::Georef kGeoref = core::Georef::projected(32632, {500000, 5000000, 0});
const core::GpsTime kT0 = core::parse_time("2024-03-05T12:00:00Z");
constexpr int kEpochs = 30;  // 10 Hz

// What a perfect INS driving north at 5 m/s, rolled 2°, pitched −1°, reports at epoch time t.
nav::NavSample truth(core::GpsTime t) {
    const double s = double((t - kT0).count()) * 1e-9;
    core::Pose p;
    p.position = {1.0, -20.0 + 5.0 * s, 1.8};
    p.attitude = core::quaternion_from_rpy(2 * kDeg, -1 * kDeg, (90 - 2 * s) * kDeg);
    nav::NavSample n = navpose::NavFrame::from_georef(kGeoref).sample(p, {0, 5, 0});
    n.t = t;
    n.fields |= nav::NavSample::kTime;
    n.quality = nav::FixQuality::RtkFixed;
    n.satellites = 12;
    return n;
}

// A sentence with field `index` (after the tag) replaced and the checksum made right again.
std::string with_field(const std::string& sentence, std::size_t index, const std::string& value) {
    std::string body = sentence.substr(1, sentence.find('*') - 1);
    std::size_t start = 0;
    for (std::size_t i = 0; i <= index; ++i) start = body.find(',', start) + 1;
    body.replace(start, body.find(',', start) - start, value);
    return nmea::frame_sentence(body);
}

std::string faulty_log() {
    nmea::EncodeOptions o;
    o.avr_time_decimals = 2;
    std::string log = nmea::encode_zda(truth(kT0), o);  // the date, first
    for (int i = 0; i < kEpochs; ++i) {
        const core::GpsTime t = kT0 + std::chrono::milliseconds(100 * i);
        nav::NavSample s = truth(t);
        std::string gga = nmea::encode_gga(s, o);
        if (i == 5) gga[12] ^= 0x01;                  // bad checksum
        if (i == 8) gga = with_field(gga, 1, "nan");  // a NaN latitude
        if (i == 16) {                                // 100 m north: a jump
            nav::NavSample j = s;
            j.lat_deg += 100.0 / 111'000.0;
            gga = nmea::encode_gga(j, o);
        }
        log += gga + nmea::encode_rmc(s, o) + nmea::encode_pashr(s, o) + nmea::encode_hdt(s, o);
        if (i >= 20 && i < 25)  // heading-only, 50 ms later: takes the last roll/pitch
            log += nmea::encode_ptnl_avr(truth(t + std::chrono::milliseconds(50)), o);
        if (i == 12) {  // an epoch stamped 1 s in the past
            const nav::NavSample b = truth(t - std::chrono::seconds(1));
            log += nmea::encode_gga(b, o) + nmea::encode_pashr(b, o);
        }
    }
    return log;
}

std::string counters_line(const std::string& out) {
    std::smatch m;
    if (!std::regex_search(out, m, std::regex("nav samples [^;\n]*"))) return "(none)";
    return m[0].str();
}

std::vector<std::vector<std::string>> csv_rows(const std::string& path) {
    std::ifstream f(path);
    std::vector<std::vector<std::string>> rows;
    std::string line;
    std::getline(f, line);  // header
    while (std::getline(f, line)) {
        std::vector<std::string> c;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');) c.push_back(x);
        rows.push_back(c);
    }
    return rows;
}

TEST(NavRules, live_and_resimulation_accept_the_same_samples_of_a_faulty_log) {
    TempDir dir;
    const std::string scene = dir.file("yard.yaml"), log = dir.file("faulty.nmea"),
                      poses = dir.file("poses.csv");
    std::ofstream(scene) << kScene;
    std::ofstream(log, std::ios::binary) << faulty_log();

    // Live: listening first, so the replay loses nothing; it runs past the log's 3 s.
    BackgroundMirage live = start_mirage(
        "live --scene " + scene +
        " --sensor vlp16 --sub-rays 1 --no-noise --position-port 0 --no-status"
        " --nav nmea:udp://127.0.0.1:0 --nav-date stream --duration 4 --first-nav-timeout 20"
        " --pose-log " +
        poses);
    ASSERT_NE(live.pipe, nullptr);
    std::smatch m;
    const std::string l = live.wait_for(std::regex("udp port [0-9]+"));
    ASSERT_TRUE(std::regex_search(l, m, std::regex("udp port ([0-9]+)"))) << live.output;
    const RunResult fake =
        run_mirage("fake-ins --log " + log + " --protocol nmea --to udp://127.0.0.1:" + m[1].str());
    ASSERT_EQ(fake.exit_code, 0) << fake.output;
    ASSERT_EQ(live.finish(), 0) << live.output;

    // Re-simulation of the same log.
    const RunResult resim = run_mirage(
        "render --scene " + scene + " --sensor vlp16 --sub-rays 1 --no-noise --nav-log " + log +
        " --nav-protocol nmea --duration 0.2 --out " + dir.file("o.las"));
    ASSERT_EQ(resim.exit_code, 0) << resim.output;

    // The same counters, named the same, from all three; and the numbers the faults make.
    const std::string want =
        "nav samples 126 applied 62, decode rejected 2 (bad checksum 1, truncated 0, invalid 1), "
        "pose rejected 3 (time backwards 2, jumps 1, not finite 0, outside the scene 0), without "
        "time 30, without "
        "pose 31, duplicates 0, re-initialisations 0";
    EXPECT_EQ(counters_line(live.output), want) << live.output;
    EXPECT_EQ(counters_line(resim.output), want) << resim.output;
    EXPECT_EQ(counters_line(fake.output), want) << fake.output;

    // The same accepted track updates: live's pose log against the re-simulation's tracks.
    const navproto::NavLog nl = navproto::read_nav_log(log, navproto::NavProtocol::Nmea);
    const navproto::NavTracks tr =
        navproto::nav_log_tracks(nl, navpose::NavFrame::from_georef(kGeoref));
    const auto rows = csv_rows(poses);
    ASSERT_EQ(rows.size(), tr.positions.size() + tr.attitudes.size());
    ASSERT_EQ(tr.positions.size(), 27u);  // 30 GGA less the bad checksum, the NaN and the jump
    ASSERT_EQ(tr.attitudes.size(), 35u);  // 30 PASHR + 5 AVR
    std::size_t p = 0, a = 0;
    for (const auto& r : rows) {
        ASSERT_GE(r.size(), 9u);
        const auto t = core::GpsTime(*core::parse_decimal_seconds(r[0]));
        if (r[1] == "position") {
            const auto& u = tr.positions.at(p++);
            EXPECT_EQ(t, u.t);
            EXPECT_EQ(Eigen::Vector3d(std::stod(r[2]), std::stod(r[3]), std::stod(r[4])), u.local);
        } else {
            const auto& u = tr.attitudes.at(a++);
            EXPECT_EQ(t, u.t);
            EXPECT_EQ(std::stod(r[5]), u.attitude.w());
            EXPECT_EQ(std::stod(r[8]), u.attitude.z());
            // Heading-only rows carry the roll of the PASHR before them, as applied.
            EXPECT_NEAR(std::stod(r[13]), 2.0, 0.01) << r[0];
        }
    }
    EXPECT_EQ(p, tr.positions.size());
    EXPECT_EQ(a, tr.attitudes.size());
    EXPECT_NE(resim.output.find("nav log: 27 positions, 35 attitudes"), std::string::npos)
        << resim.output;
}

}  // namespace
}  // namespace mirage::test
