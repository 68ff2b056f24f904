// SPDX-License-Identifier: Apache-2.0
// Re-simulation from recorded navigation logs: logs written by our own encoders from a known
// trajectory decode back to it (NMEA, NovAtel, OxTS CAN), rst39.log gives its 4 s drive, a render
// over it produces points, and bad logs are counted, IoError or ConfigError.
#include "mirage/navproto/nav_log.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <regex>

#include "cli_run.hpp"
#include "mirage/core/error.hpp"
#include "mirage/core/time.hpp"
#include "mirage/navcan/candump.hpp"
#include "mirage/navio/fake_ins.hpp"
#include "mirage/navproto/protocol.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

using navproto::NavProtocol;
constexpr double kDeg = std::numbers::pi / 180.0;

// 3 s drive: accelerating, climbing, rolled and pitched, heading swinging 340° -> 20° through
// north (ENU yaw 110° -> 70°), so a wrong wrap shows as a 360° error.
core::Trajectory truth_trajectory(core::GpsTime t0) {
    std::vector<core::StampedPose> s;
    for (int i = 0; i <= 300; ++i) {
        const double t = i * 0.01;
        core::StampedPose p;
        p.t = t0 + core::Nanos(std::int64_t(i) * 10'000'000);
        p.pose.position = {3.0 + 10.0 * t, -4.0 + 2.0 * t * t, 5.0 + 0.1 * t};
        p.pose.attitude =
            core::quaternion_from_rpy(2.0 * kDeg, -3.0 * kDeg, (110.0 - 40.0 * t / 3.0) * kDeg);
        s.push_back(p);
    }
    return core::Trajectory(std::move(s), core::Interpolation::Linear);
}

const core::GpsTime kT0 = core::parse_time("2024-03-05T12:00:00Z");
const navpose::NavFrame kFrame = navpose::NavFrame::tangent_plane(48.1, 11.5, 520.0);

// Writes `epochs` epochs at `rate_hz` of the fake INS's messages as a log file (byte protocols:
// raw bytes; CAN: candump -L with Unix timestamps), as `mirage live --nav-record` would.
void write_log(const std::string& path, navproto::NavProtocol p, const core::Trajectory& truth,
               double rate_hz, int epochs) {
    navio::FakeInsConfig cfg;
    cfg.protocol = p;
    cfg.rate_hz = rate_hz;
    navio::FakeIns ins(truth, kFrame, cfg);
    auto enc = navproto::make_nav_encoder(p, rate_hz);
    const auto period = core::Nanos(std::llround(1e9 / rate_hz));
    if (navproto::is_can(p)) {
        navcan::CandumpWriter w(path);
        for (int i = 0; i < epochs; ++i) {
            const core::GpsTime t = kT0 + period * i;
            const auto frames = enc->encode_frames(ins.sample_at(t, kT0), std::uint64_t(i));
            std::int64_t unix_ns = core::unix_ns_from_gps(t);
            for (const auto& f : frames) w.write(unix_ns += 100'000, "can0", f);
        }
        ASSERT_TRUE(w.close());
    } else {
        std::ofstream f(path, std::ios::binary);
        for (int i = 0; i < epochs; ++i) {
            const core::GpsTime t = kT0 + period * i;
            const auto b = enc->encode_bytes(ins.sample_at(t, kT0), std::uint64_t(i));
            f.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
        }
    }
}

double heading_deg(const Eigen::Quaterniond& q) {
    const Eigen::Vector3d g = kFrame.geodetic_from_local(Eigen::Vector3d::Zero());
    return kFrame.ned_euler(q, g.x(), g.y()).z() / kDeg;
}

double wrapped_diff_deg(double a, double b) {
    double d = std::fmod(a - b, 360.0);
    if (d > 180.0) d -= 360.0;
    if (d < -180.0) d += 360.0;
    return d;
}

struct RoundTrip {
    double max_pos_m = 0, max_heading_deg = 0, max_angle_deg = 0;
    std::size_t poses = 0;
    core::Nanos span{0};
};

RoundTrip round_trip(navproto::NavProtocol p, const std::string& name) {
    TempDir dir;
    const core::Trajectory truth = truth_trajectory(kT0);
    const std::string path = dir.file(name);
    write_log(path, p, truth, 10.0, 30);
    const navproto::NavLog log = navproto::read_nav_log(path, p);
    EXPECT_EQ(log.stats.rejected(), 0u) << navproto::nav_log_summary(log);
    const core::Trajectory got = navproto::nav_log_trajectory(log, kFrame);
    RoundTrip r;
    r.poses = got.samples().size();
    r.span = got.end() - got.begin();
    EXPECT_EQ(got.begin(), kT0);
    for (const auto& sp : got.samples()) {
        const core::Pose want = truth.at(sp.t);
        r.max_pos_m = std::max(r.max_pos_m, (sp.pose.position - want.position).norm());
        r.max_heading_deg = std::max(
            r.max_heading_deg,
            std::abs(wrapped_diff_deg(heading_deg(sp.pose.attitude), heading_deg(want.attitude))));
        r.max_angle_deg =
            std::max(r.max_angle_deg, sp.pose.attitude.angularDistance(want.attitude) / kDeg);
    }
    std::printf(
        "%s: %zu poses over %.3f s, position error max %.2e m, heading %.4f deg, "
        "attitude %.4f deg\n",
        name.c_str(), r.poses, double(r.span.count()) * 1e-9, r.max_pos_m, r.max_heading_deg,
        r.max_angle_deg);
    return r;
}

TEST(NavLogResim, nmea_log_of_a_known_drive_resimulates_to_it) {
    const RoundTrip r = round_trip(navproto::NavProtocol::Nmea, "drive.nmea");
    EXPECT_EQ(r.poses, 30u);  // GGA and PASHR share every epoch's time
    EXPECT_EQ(r.span, std::chrono::milliseconds(2900));
    EXPECT_LT(r.max_pos_m, 0.002);       // 7 minute decimals, mm heights
    EXPECT_LT(r.max_heading_deg, 0.01);  // PASHR: 0.01° digits
    EXPECT_LT(r.max_angle_deg, 0.012);   // roll and pitch rounded to 0.01° as well
}

TEST(NavLogResim, novatel_log_of_a_known_drive_resimulates_to_it) {
    const RoundTrip r = round_trip(navproto::NavProtocol::Novatel, "drive.gps");
    EXPECT_EQ(r.poses, 30u);
    EXPECT_EQ(r.span, std::chrono::milliseconds(2900));
    EXPECT_LT(r.max_pos_m, 0.001);  // doubles on the wire
    EXPECT_LT(r.max_heading_deg, 0.01);
    EXPECT_LT(r.max_angle_deg, 0.01);
}

TEST(NavLogResim, oxts_can_candump_of_a_known_drive_resimulates_to_it) {
    const RoundTrip r = round_trip(navproto::NavProtocol::OxtsCan, "drive.log");
    EXPECT_EQ(r.poses, 30u);
    EXPECT_EQ(r.span, std::chrono::milliseconds(2900));
    EXPECT_LT(r.max_pos_m, 0.02);  // 1e-7° lat/lon (1.1 cm), mm altitude
    EXPECT_LT(r.max_heading_deg, 0.01);
    EXPECT_LT(r.max_angle_deg, 0.012);
}

TEST(NavLogResim, byte_log_messages_carry_their_own_times) {
    TempDir dir;
    const core::Trajectory truth = truth_trajectory(kT0);
    const std::string path = dir.file("drive.gps");
    write_log(path, navproto::NavProtocol::Novatel, truth, 10.0, 30);
    const navproto::NavLog log = navproto::read_nav_log(path, navproto::NavProtocol::Novatel);
    // One INSPVAS per epoch plus BESTPOS once a second (epochs 0, 10, 20): 33 messages.
    ASSERT_EQ(log.messages.size(), 33u);
    std::size_t covered = 0;
    for (const auto& m : log.messages) {
        EXPECT_TRUE(m.timed);
        EXPECT_EQ((m.t - kT0).count() % 100'000'000, 0);
        covered += m.size;
    }
    EXPECT_EQ(covered, log.bytes.size());
    EXPECT_EQ(log.messages.back().t - kT0, std::chrono::milliseconds(2900));
}

TEST(NavLogResim, rst39_with_an_origin_is_a_4_s_drive_turning_from_10_5_to_74_4_deg) {
    MIRAGE_NAVIO_OR_SKIP(path, "rst39.log");
    const navproto::NavLog log = navproto::read_nav_log(path.string(), navproto::NavProtocol::Nmea);
    std::printf("%s\n", navproto::nav_log_summary(log).c_str());
    const navpose::NavFrame frame = navproto::parse_nav_origin("42.0957,-88.0340,200");
    navproto::NavTrackStats st;
    const core::Trajectory tr = navproto::nav_log_trajectory(log, frame, {}, &st);
    EXPECT_EQ(st.positions, 40u);   // 40 GGA
    EXPECT_EQ(st.attitudes, 100u);  // every PASHR (25 Hz), the first one (before RMC) included
    // 20:41:32.000 UTC on 2014-02-19 (RMC date) = GPS + 16 s leap seconds.
    EXPECT_EQ(tr.begin(), core::parse_time("2014-02-19T20:41:32Z"));
    EXPECT_EQ(tr.end() - tr.begin(), std::chrono::seconds(4));
    const auto hdg = [&](core::GpsTime t) {
        const core::Pose p = tr.at(t);
        const Eigen::Vector3d g = frame.geodetic_from_local(p.position);
        return frame.ned_euler(p.attitude, g.x(), g.y()).z() / kDeg;
    };
    const double h0 = hdg(tr.begin()), h1 = hdg(tr.end());
    std::printf("rst39: %zu poses, heading %.3f -> %.3f deg, start local (%.2f, %.2f, %.2f) m\n",
                tr.samples().size(), h0, h1, tr.at(tr.begin()).position.x(),
                tr.at(tr.begin()).position.y(), tr.at(tr.begin()).position.z());
    EXPECT_NEAR(h0, 10.51, 0.01);
    EXPECT_NEAR(h1, 74.42, 0.01);
    // First fix 4205.733715N 08802.040978W, MSL 221.921 (no undulation): ~16 m south of the origin.
    const Eigen::Vector3d fix =
        frame.local_from_geodetic(42.0 + 5.733715 / 60.0, -(88.0 + 2.040978 / 60.0), 221.921);
    EXPECT_LT((tr.at(core::parse_time("2014-02-19T20:41:32.1Z")).position - fix).norm(), 1e-6);
    EXPECT_NEAR(fix.z(), 21.921, 0.01);
}

TEST(NavLogResim, render_over_rst39_produces_points) {
    MIRAGE_NAVIO_OR_SKIP(path, "rst39.log");
    TempDir dir;
    const std::string scene = dir.file("flat.yaml");
    std::ofstream(scene) << "georef: {epsg: 32616, anchor: [0, 0, 0]}\n"
                            "materials:\n  ground: {reflectance: 0.3, classification: 2}\n"
                            "objects:\n  - {type: plane, material: ground, size: [500, 500]}\n";
    const RunResult r = run_mirage("render --scene " + scene +
                                   " --sensor vlp16 --sub-rays 1 "
                                   "--no-noise --nav-log " +
                                   path.string() +
                                   " --nav-protocol nmea --nav-origin 42.0957,-88.0340,200 "
                                   "--duration 0.2 --out " +
                                   dir.file("o.las"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"((\d+) points\))"))) << r.output;
    std::printf("render over rst39: %s points in 0.2 s\n", m[1].str().c_str());
    EXPECT_GT(std::stoull(m[1].str()), 1000u);
}

TEST(NavLogBad, malformed_sentences_are_counted_and_skipped) {
    TempDir dir;
    const core::Trajectory truth = truth_trajectory(kT0);
    const std::string good = dir.file("good.nmea");
    write_log(good, navproto::NavProtocol::Nmea, truth, 10.0, 30);
    std::ifstream in(good);
    std::ofstream out(dir.file("bad.nmea"));
    int n = 0;
    for (std::string line; std::getline(in, line); ++n) {
        if (n == 7) line[line.size() / 2] ^= 0x01;  // checksum mismatch
        out << line << '\n';
        if (n == 12) out << "$GPGGA,garbage*00\r\n";
        if (n == 20) out << "\x01\x02 line noise\r\n";
    }
    out.close();
    const navproto::NavLog log =
        navproto::read_nav_log(dir.file("bad.nmea"), navproto::NavProtocol::Nmea);
    const std::string sum = navproto::nav_log_summary(log);
    std::printf("%s\n", sum.c_str());
    EXPECT_EQ(log.stats.decode.bad_checksum, 2u);
    EXPECT_GT(log.stats.decode.garbage_bytes, 0u);
    EXPECT_NE(sum.find("2 bad checksum"), std::string::npos);
    // The drive survives: the lost sentence's epoch is interpolated from its neighbours (the
    // truth accelerates at 4 m/s² north: a/8·(2·0.1 s)² = 2 cm off there), the rest exact.
    const core::Trajectory tr = navproto::nav_log_trajectory(log, kFrame);
    EXPECT_EQ(tr.end() - tr.begin(), std::chrono::milliseconds(2900));
    int off = 0;
    for (const auto& sp : tr.samples()) {
        const double e = (sp.pose.position - truth.at(sp.t).position).norm();
        EXPECT_LT(e, 0.021);
        off += e > 0.002 ? 1 : 0;
    }
    EXPECT_LE(off, 1);
}

TEST(NavLogBad, malformed_candump_lines_are_counted_with_the_first_line_number) {
    TempDir dir;
    const std::string path = dir.file("drive.log");
    write_log(path, navproto::NavProtocol::OxtsCan, truth_trajectory(kT0), 10.0, 10);
    std::ofstream(path, std::ios::app) << "(17xx.000) can0 601#00\n(1709640000.000000) can0 6G1#\n";
    const navproto::NavLog log = navproto::read_nav_log(path, navproto::NavProtocol::OxtsCan);
    EXPECT_EQ(log.stats.candump.rejected(), 2u);
    EXPECT_GT(log.stats.candump.first_bad_line, 0u);
    EXPECT_EQ(navproto::nav_log_trajectory(log, kFrame).samples().size(), 10u);
}

TEST(NavLogBad, unreadable_file_is_an_io_error_naming_it) {
    try {
        (void)navproto::read_nav_log("/nonexistent/drive.nmea", navproto::NavProtocol::Nmea);
        FAIL() << "no exception";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("nav log '/nonexistent/drive.nmea'"),
                  std::string::npos);
    }
    EXPECT_THROW((void)navproto::read_nav_log("/nonexistent/x.log", navproto::NavProtocol::OxtsCan),
                 IoError);
}

TEST(NavLogBad, log_without_a_pose_is_a_config_error_naming_it) {
    TempDir dir;
    const std::string path = dir.file("empty.nmea");
    // Time and velocity but no position or attitude: RMC and ZDA only.
    std::ofstream(path) << "$GPZDA,204136.000,19,02,2014,,*59\r\nnot nmea at all\r\n";
    const navproto::NavLog log = navproto::read_nav_log(path, navproto::NavProtocol::Nmea);
    try {
        (void)navproto::nav_log_trajectory(log, kFrame);
        FAIL() << "no exception";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("nav log '" + path + "': no usable pose"), std::string::npos) << what;
    }
    // The wrong protocol for a file: nothing decodes, same error.
    write_log(dir.file("drive.nmea"), navproto::NavProtocol::Nmea, truth_trajectory(kT0), 10.0, 5);
    const navproto::NavLog wrong =
        navproto::read_nav_log(dir.file("drive.nmea"), navproto::NavProtocol::Novatel);
    EXPECT_THROW((void)navproto::nav_log_trajectory(wrong, kFrame), ConfigError);
}

TEST(NavLogBad, nav_origin_must_be_three_numbers) {
    EXPECT_THROW((void)navproto::parse_nav_origin("42.1,-88"), ConfigError);
    EXPECT_THROW((void)navproto::parse_nav_origin("42.1,x,1"), ConfigError);
    EXPECT_THROW((void)navproto::parse_nav_origin("95,0,0"), ConfigError);
    const auto f = navproto::parse_nav_origin("42.0957,-88.0340,200");
    EXPECT_LT(f.local_from_geodetic(42.0957, -88.0340, 200).norm(), 1e-6);
}

}  // namespace
}  // namespace mirage::test
