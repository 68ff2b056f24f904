// SPDX-License-Identifier: Apache-2.0
// Recording the navigation input while running live (issue 5 item 3) and the pose log:
// `mirage live --nav-record` keeps the raw bytes (NMEA) or a candump -L log (CAN) that decode
// back to what live applied; `--pose-log` keeps every applied track update; a write error fails
// the command and never leaves a line cut in half.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <regex>
#include <sstream>

#include "cli_run.hpp"
#include "mirage/core/time.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/navcan/candump.hpp"
#include "mirage/navcan/oxts_can.hpp"
#include "mirage/navio/nav_recorder.hpp"
#include "mirage/nmea/nmea_decoder.hpp"
#include "test_paths.hpp"
#include "utm_ground_scene.hpp"

namespace mirage::test {
namespace {

constexpr const char* kScene = kUtmGroundScene;

const char* kLive =
    " --sensor vlp16 --sub-rays 1 --no-noise --position-port 0 --duration 2 --no-status"
    " --first-nav-timeout 20";

std::uint64_t figure(const std::string& out, const std::string& re) {
    std::smatch m;
    if (!std::regex_search(out, m, std::regex(re))) return ~std::uint64_t{0};
    return std::stoull(m[1].str());
}

std::string slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

TEST(LiveRecord, nmea_raw_capture_decodes_to_the_samples_live_applied) {
    TempDir tmp;
    const std::string scene = tmp.file("yard.yaml"), link = tmp.file("ins");
    std::ofstream(scene) << kScene;
    const std::string rec = tmp.file("nav.nmea"), poses = tmp.file("poses.csv");
    // The fake INS creates the pty first; live then reads it for 2 s.
    FILE* fake = ::popen((std::string(MIRAGE_EXE) + " fake-ins --scene " + scene +
                          " --trajectory static:0,0,1.8,0,0,30 --protocol nmea --rate 25"
                          " --duration 6 --to pty:" +
                          link + " 2>&1")
                             .c_str(),
                         "r");
    ASSERT_NE(fake, nullptr);
    std::string fake_out;
    char buf[1024];
    while (std::fgets(buf, sizeof buf, fake)) {
        fake_out += buf;
        if (fake_out.find("t0 gps:") != std::string::npos) break;
    }
    const RunResult r = run_mirage("live --scene " + scene + " --nav nmea:" + link + kLive +
                                   " --nav-record " + rec + " --pose-log " + poses);
    while (std::size_t n = std::fread(buf, 1, sizeof buf, fake)) fake_out.append(buf, n);
    ::pclose(fake);
    ASSERT_EQ(r.exit_code, 0) << r.output << fake_out;

    const std::uint64_t applied = figure(r.output, "applied ([0-9]+)");
    const std::uint64_t rows = figure(r.output, "pose log: ([0-9]+) samples");
    EXPECT_EQ(figure(r.output, "pose rejected ([0-9]+)"), 0u) << r.output;
    EXPECT_EQ(figure(r.output, "decode rejected ([0-9]+)"), 0u) << r.output;
    EXPECT_GT(applied, 50u) << r.output;  // 25 Hz GGA + PASHR for ~2.5 s
    EXPECT_EQ(rows, applied) << r.output;
    EXPECT_EQ(lines_of(slurp(poses)).size(), rows + 1);  // + the header row

    // Decode the capture as live did (host date hint): position and attitude samples = applied.
    const std::string raw = slurp(rec);
    EXPECT_EQ(raw.size(),
              figure(r.output, "nav record: [0-9]+ chunks \\(raw\\) \\(([0-9]+) bytes"));
    nmea::NmeaDecoder d;
    const auto unix_s = std::time(nullptr);
    d.set_date_hint(nmea::Date::from_unix_days(unix_s / 86'400));
    std::uint64_t pose_samples = 0, samples = 0;
    d.feed(std::string_view(raw), [&](const nav::NavSample& s) {
        ++samples;
        if (s.has(nav::NavSample::kTime) &&
            (s.has(nav::NavSample::kPosition) || s.has(nav::NavSample::kAttitude)))
            ++pose_samples;
    });
    std::printf("[ nmea record ] %zu bytes, %llu samples, %llu poses; live applied %llu\n",
                raw.size(), static_cast<unsigned long long>(samples),
                static_cast<unsigned long long>(pose_samples),
                static_cast<unsigned long long>(applied));
    EXPECT_EQ(pose_samples, applied);
    EXPECT_EQ(samples, figure(r.output, "nav samples ([0-9]+)"));
    EXPECT_EQ(d.counters().rejected(), 0u);
}

TEST(LiveRecord, can_candump_log_parses_back_to_the_frames_the_bus_delivered) {
    TempDir tmp;
    const std::string scene = tmp.file("yard.yaml"), rec = tmp.file("nav.log");
    std::ofstream(scene) << kScene;
    const std::int64_t before = hostclock::realtime_ns();
    const RunResult r = run_mirage("live --scene " + scene +
                                   " --nav oxts-can:memory:vcan0 --fake-ins static:0,0,1.8,0,0,30" +
                                   kLive + " --nav-record " + rec);
    const std::int64_t after = hostclock::realtime_ns();
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const std::uint64_t rx = figure(r.output, "nav bus: rx frames ([0-9]+)");
    const std::uint64_t err = figure(r.output, "error frames ([0-9]+),");
    ASSERT_GT(rx, 500u) << r.output;
    EXPECT_EQ(err, 0u);
    EXPECT_EQ(figure(r.output, "nav record: ([0-9]+) frames"), rx + err);

    navcan::CandumpReader reader(rec);
    navcan::OxtsCanDecoder dec;
    navcan::CandumpRecord c;
    std::uint64_t frames = 0, samples = 0;
    std::int64_t prev = 0;
    bool ordered = true, in_run = true, ifname_ok = true;
    while (reader.next(c)) {
        ++frames;
        ordered = ordered && c.stamped.time_ns >= prev;
        prev = c.stamped.time_ns;
        // Host CLOCK_REALTIME at reception, truncated to µs by the -L format.
        in_run = in_run && c.stamped.time_ns >= before / 1000 * 1000 && c.stamped.time_ns <= after;
        ifname_ok = ifname_ok && c.interface == "vcan0";
        dec.feed(c.stamped.frame, [&](const nav::NavSample&) { ++samples; });
    }
    std::printf("[ candump record ] %llu frames (bus rx %llu) -> %llu samples (live %llu)\n",
                static_cast<unsigned long long>(frames), static_cast<unsigned long long>(rx),
                static_cast<unsigned long long>(samples),
                static_cast<unsigned long long>(figure(r.output, "nav samples ([0-9]+)")));
    EXPECT_EQ(reader.stats().rejected(), 0u);
    EXPECT_EQ(frames, rx);
    EXPECT_TRUE(ordered);
    EXPECT_TRUE(in_run);
    EXPECT_TRUE(ifname_ok);
    EXPECT_EQ(samples, figure(r.output, "nav samples ([0-9]+)"));

    // can-utils' own reader accepts it: log2asc writes one ASC line per frame.
    if (::access("/usr/bin/log2asc", X_OK) != 0) {
        std::printf("[ SKIPPED part ] log2asc not installed (Debian can-utils)\n");
        return;
    }
    const std::string asc = tmp.file("nav.asc");
    const int st = std::system(("/usr/bin/log2asc -I " + rec + " -O " + asc + " vcan0").c_str());
    ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0);
    std::uint64_t asc_frames = 0;
    for (const auto& l : lines_of(slurp(asc)))
        if (l.find(" Rx ") != std::string::npos) ++asc_frames;
    std::printf("[ log2asc ] %llu Rx lines\n", static_cast<unsigned long long>(asc_frames));
    EXPECT_EQ(asc_frames, frames);
}

TEST(LiveRecord, pose_log_write_error_fails_the_command_with_a_clear_message) {
    TempDir tmp;
    const std::string scene = tmp.file("yard.yaml");
    std::ofstream(scene) << kScene;
    const RunResult r = run_mirage("live --scene " + scene +
                                   " --nav oxts-can:memory:full --fake-ins static:0,0,1.8,0,0,30" +
                                   kLive + " --pose-log /dev/full");
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("mirage: error: live: --pose-log '/dev/full': write failed after 0 "
                            "units (0 bytes): No space left on device"),
              std::string::npos)
        << r.output;
    // The run itself completed (summary printed) before the error was reported.
    EXPECT_NE(r.output.find("mirage live: "), std::string::npos);
}

TEST(RecordFile, write_error_cuts_the_file_back_to_the_last_whole_line) {
    TempDir tmp;
    const std::string path = tmp.file("cut.csv");
    // A 100 000-byte file size limit stands in for a full disk (EFBIG instead of ENOSPC).
    ::signal(SIGXFSZ, SIG_IGN);
    rlimit old{};
    ::getrlimit(RLIMIT_FSIZE, &old);
    rlimit lim = old;
    lim.rlim_cur = 100'000;
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &lim), 0);
    bool ok = true;
    std::string error;
    std::uint64_t units = 0;
    {
        navio::RecordFile f(path, "test 'cut.csv'");
        const std::string line(29, 'x');  // 30 bytes with '\n': 100 000 is not a multiple
        for (int i = 0; i < 10'000; ++i) f.append(line + "\n");
        ok = f.close();
        error = f.error();
        units = f.units();
    }
    ::setrlimit(RLIMIT_FSIZE, &old);
    EXPECT_FALSE(ok);
    EXPECT_NE(error.find("test 'cut.csv': write failed after"), std::string::npos) << error;
    EXPECT_NE(error.find("File too large"), std::string::npos) << error;
    const std::string text = slurp(path);
    // 64 KiB flushes land on whole lines; the one that hit the limit was cut back.
    EXPECT_EQ(text.size() % 30, 0u);
    EXPECT_EQ(text.size(), units * 30);
    EXPECT_LE(text.size(), 100'000u);
    EXPECT_GT(text.size(), 60'000u);
    EXPECT_EQ(text.back(), '\n');
}

TEST(PoseLog, rows_read_back_to_the_exact_values_applied) {
    TempDir tmp;
    const std::string path = tmp.file("p.csv");
    nav::NavSample s;
    s.fields = nav::NavSample::kTime | nav::NavSample::kPosition | nav::NavSample::kHeightIsMsl |
               nav::NavSample::kAttitude;
    s.t = core::GpsTime(core::Nanos(1'076'877'708'100'000'001));
    s.lat_deg = 42.095561916666667;
    s.lon_deg = -88.034016299999999;
    s.height_m = 221.921;
    s.roll_rad = -0.1;
    s.pitch_rad = 0.2;
    s.heading_rad = 350.0 * M_PI / 180.0;  // a heading near north stays in [0, 360)
    const Eigen::Vector3d local(12.345678901234, -0.1, 1e-7);
    const Eigen::Quaterniond q(0.5, -0.5, 0.5, 0.5);
    navpose::PositionUpdate pu;
    pu.t = s.t;
    pu.local = local;
    navpose::AttitudeUpdate au;
    au.t = s.t;
    au.attitude = q;
    au.ned_rpy = {s.roll_rad, s.pitch_rad, s.heading_rad};
    {
        navio::PoseLog log(path);
        log.position(s, pu);
        log.attitude(au);
        ASSERT_TRUE(log.close());
        EXPECT_EQ(log.rows(), 2u);
    }
    const auto l = lines_of(slurp(path));
    ASSERT_EQ(l.size(), 3u);
    EXPECT_EQ(l[0],
              "gps_time_s,kind,x_m,y_m,z_m,qw,qx,qy,qz,lat_deg,lon_deg,h_m,h_ref,roll_deg,"
              "pitch_deg,heading_deg");
    auto cells = [](const std::string& line) {
        std::vector<std::string> c;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');) c.push_back(x);
        if (!line.empty() && line.back() == ',') c.emplace_back();
        return c;
    };
    const auto p = cells(l[1]), a = cells(l[2]);
    ASSERT_EQ(p.size(), 16u);
    ASSERT_EQ(a.size(), 16u);
    EXPECT_EQ(p[0], "1076877708.100000001");
    EXPECT_EQ(p[1], "position");
    EXPECT_EQ(std::stod(p[2]), local.x());
    EXPECT_EQ(std::stod(p[3]), local.y());
    EXPECT_EQ(std::stod(p[4]), local.z());
    EXPECT_EQ(p[5], "");
    EXPECT_EQ(std::stod(p[9]), s.lat_deg);
    EXPECT_EQ(std::stod(p[10]), s.lon_deg);
    EXPECT_EQ(std::stod(p[11]), 221.921);
    EXPECT_EQ(p[12], "msl");
    EXPECT_EQ(p[15], "");
    EXPECT_EQ(a[1], "attitude");
    EXPECT_EQ(a[2], "");
    EXPECT_EQ(std::stod(a[5]), 0.5);
    EXPECT_EQ(std::stod(a[6]), -0.5);
    EXPECT_NEAR(std::stod(a[13]), -0.1 * 180 / M_PI, 1e-12);
    EXPECT_NEAR(std::stod(a[14]), 0.2 * 180 / M_PI, 1e-12);
    EXPECT_NEAR(std::stod(a[15]), 350.0, 1e-12);
}

TEST(NavRecorder, candump_interface_names_follow_the_bus_spec) {
    EXPECT_EQ(navio::candump_ifname("socketcan:can1"), "can1");
    EXPECT_EQ(navio::candump_ifname("memory:vcan0"), "vcan0");
    EXPECT_EQ(navio::candump_ifname("slcan:/dev/pts/3?bitrate=500000"), "slcan0");
    EXPECT_EQ(navio::candump_ifname("gsusb:1d50:606f"), "can0");
    EXPECT_EQ(navio::candump_ifname("memory:a b/c?x=1"), "a_b_c");
    EXPECT_EQ(navio::candump_ifname("memory:abcdefghijklmnopqrstuvwxyz").size(), 21u);
}

}  // namespace
}  // namespace mirage::test
