// SPDX-License-Identifier: Apache-2.0
// A real NMEA peer (issue 4 item 6): gpsd's gpsfake plays the OxTS RT log rst39.log into a pty
// and `mirage live` reads that pty; the poses it applies must follow the log.
//
// How mirage reads what gpsfake writes: gpsfake opens a pty per log, starts "gpsd" and hands it
// the pty's slave path over gpsd's control socket (`+/dev/pts/N\r\n`, answered `OK\n`), then
// writes one sentence per cycle into the master. `-m PROG` (monitor prefix) makes gpsfake run
// `PROG gpsd -b -N -S port -F socket …`, so a 20-line Python stand-in for gpsd takes that
// place: it serves the control socket, publishes the pty path, and answers OK only once
// `mirage live` has the pty open — what gpsd does after opening a device. gpsfake itself is
// unchanged (its pty set-up, packetiser, pacing `-c`, single shot `-1`), so mirage reads exactly
// the bytes a gpsd would. The alternatives re-emit gpsd's parse (gpsd's NMEA output loses
// PASHR and the decimals) or skip gpsfake (`-t`/`-u` feed TCP/UDP, not a serial line).
// gpsfake with -1 and no client ends by its timeout (-W 1 s) after the last sentence; then the
// test stops `mirage live` with SIGINT, which must flush and close the pose log.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "mirage/core/time.hpp"
#include "mirage/navpose/nav_frame.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

using Clock = std::chrono::steady_clock;

// Stands in for gpsd under gpsfake -m: argv[1] = folder for the hand-shake files, then gpsd's
// own command line (…, -F <control socket>, …).
constexpr const char* kFakeGpsd = R"(import os, socket, sys, time
d = sys.argv[1]
rest = sys.argv[2:]
path = rest[rest.index('-F') + 1]
srv = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
srv.bind(path)
srv.listen(4)
while True:
    c, _ = srv.accept()
    cmd = c.recv(512).decode(errors='replace').strip('\r\n\x00 ')
    if cmd.startswith('+'):
        with open(os.path.join(d, 'device.tmp'), 'w') as f:
            f.write(cmd[1:])
        os.rename(os.path.join(d, 'device.tmp'), os.path.join(d, 'device'))
        deadline = time.time() + 60
        while not os.path.exists(os.path.join(d, 'go')) and time.time() < deadline:
            time.sleep(0.01)
    c.sendall(b'OK\n')
    c.close()
)";

std::string slurp(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

std::vector<std::string> split(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : s) {
        if (c == sep) {
            out.push_back(cur);
            cur.clear();
        } else if (c != '\r') {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

// A child in its own process group, output to a file; stopped and reaped by id at the end.
class Child {
  public:
    Child(const std::vector<std::string>& argv, const std::string& out,
          const std::vector<std::string>& env = {}) {
        pid_ = ::fork();
        if (pid_ == 0) {
            ::setpgid(0, 0);
            const int in = ::open("/dev/null", O_RDONLY);
            const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            ::dup2(in, 0);
            ::dup2(fd, 1);
            ::dup2(fd, 2);
            for (const auto& e : env) ::putenv(const_cast<char*>(e.c_str()));
            std::vector<char*> args;
            for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
            args.push_back(nullptr);
            ::execv(args[0], args.data());
            ::_exit(127);
        }
        if (pid_ > 0) ::setpgid(pid_, pid_);
    }
    ~Child() {
        if (pid_ > 0 && status_ < 0) {
            ::kill(-pid_, SIGKILL);
            int st = 0;
            ::waitpid(pid_, &st, 0);
        }
    }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;
    pid_t pid() const { return pid_; }
    void signal(int sig) const { ::kill(pid_, sig); }
    // Exit code (128 + signal), or -1 if still running at `deadline`.
    int wait_until(Clock::time_point deadline) {
        while (status_ < 0) {
            int st = 0;
            const pid_t r = ::waitpid(pid_, &st, WNOHANG);
            if (r == pid_) {
                status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
                // Whatever it left in its group (gpsfake's gpsd stand-in) goes too.
                ::kill(-pid_, SIGKILL);
                break;
            }
            if (Clock::now() > deadline) return -1;
            ::usleep(20'000);
        }
        return status_;
    }
    bool running() { return wait_until(Clock::now() - std::chrono::seconds(1)) < 0; }

  private:
    pid_t pid_ = -1;
    int status_ = -1;
};

// Polls `pred` until true or the deadline; false on timeout.
template <class Pred>
bool eventually(Pred pred, std::chrono::seconds limit) {
    const auto deadline = Clock::now() + limit;
    while (!pred()) {
        if (Clock::now() > deadline) return false;
        ::usleep(20'000);
    }
    return true;
}

struct Expected {
    core::GpsTime t;
    double lat = 0, lon = 0, h = 0, heading_deg = 0;
};

// GPS time of `hhmmss.sss` on 2014-02-19 (the log's RMC/ZDA date), with the leap-second table.
core::GpsTime log_time(const std::string& hhmmss) {
    const std::int64_t days = 16'120;  // 2014-02-19 − 1970-01-01
    const std::int64_t hh = std::stoll(hhmmss.substr(0, 2)), mm = std::stoll(hhmmss.substr(2, 2));
    const core::Nanos sec = *core::parse_decimal_seconds(hhmmss.substr(4));
    const std::int64_t unix_ns =
        (days * 86'400 + hh * 3600 + mm * 60) * 1'000'000'000 + sec.count();
    return core::gps_from_unix_ns(unix_ns);
}

double nmea_deg(const std::string& v, const std::string& hemi, int deg_digits) {
    const double d = std::stod(v.substr(0, static_cast<std::size_t>(deg_digits))) +
                     std::stod(v.substr(static_cast<std::size_t>(deg_digits))) / 60.0;
    return hemi == "S" || hemi == "W" ? -d : d;
}

TEST(LiveGpsfake, poses_follow_rst39_played_by_gpsfake_into_a_pty) {
    MIRAGE_NAVIO_OR_SKIP(log, "rst39.log");
    for (const char* p : {"/usr/bin/gpsfake", "/usr/sbin/gpsd", "/usr/bin/python3"})
        if (::access(p, X_OK) != 0)
            GTEST_SKIP() << p << " not installed (Debian gpsd, gpsd-clients): no real NMEA peer";
    TempDir tmp;
    const std::string wrapper = tmp.file("fake_gpsd.py");
    std::ofstream(wrapper) << kFakeGpsd;

    // The log's sentences after the first date (RMC/ZDA): what live can time and apply.
    std::vector<Expected> gga, pashr;
    std::vector<std::string> sentences;
    {
        std::ifstream f(log);
        bool dated = false;
        for (std::string l; std::getline(f, l);) {
            if (!l.empty() && l.back() == '\r') l.pop_back();
            if (l.empty() || l[0] != '$') continue;
            sentences.push_back(l);
            const auto c = split(l.substr(0, l.find('*')), ',');
            if (c[0] == "$GPRMC" || c[0] == "$GPZDA") dated = true;
            if (!dated) continue;
            if (c[0] == "$GPGGA") {
                Expected e;
                e.t = log_time(c[1]);
                e.lat = nmea_deg(c[2], c[3], 2);
                e.lon = nmea_deg(c[4], c[5], 3);
                e.h = std::stod(c[9]);  // MSL; the separation field is empty (--undulation 0)
                gga.push_back(e);
            } else if (c[0] == "$PASHR") {
                Expected e;
                e.t = log_time(c[1]);
                e.heading_deg = std::stod(c[2]);
                pashr.push_back(e);
            }
        }
    }
    ASSERT_EQ(gga.size(), 40u);
    ASSERT_EQ(pashr.size(), 99u);  // the first PASHR comes before the first date

    // gpsfake: single shot, one sentence per 25 ms (the log's 100 PASHR span 4 s).
    Child gpsfake({"/usr/bin/gpsfake", "-1", "-q", "-c", "0.025", "-W", "1", "-m",
                   "/usr/bin/python3 " + wrapper + " " + tmp.path().string(), log.string()},
                  tmp.file("gpsfake.out"), {"TMPDIR=" + tmp.path().string()});
    const std::string device_file = tmp.file("device");
    ASSERT_TRUE(
        eventually([&] { return std::filesystem::exists(device_file) || !gpsfake.running(); },
                   std::chrono::seconds(30)))
        << "gpsfake did not hand over a pty: " << slurp(tmp.file("gpsfake.out"));
    ASSERT_TRUE(std::filesystem::exists(device_file)) << slurp(tmp.file("gpsfake.out"));
    const std::string device = slurp(device_file);
    ASSERT_EQ(device.rfind("/dev/pts/", 0), 0u) << device;

    const std::string poses = tmp.file("poses.csv"), rec = tmp.file("rst39.nmea");
    const std::string live_out = tmp.file("live.out");
    Child live({MIRAGE_EXE,
                "live",
                "--sensor",
                "vlp16",
                "--sub-rays",
                "1",
                "--no-noise",
                "--nav",
                "nmea:" + device,
                "--nav-date",
                "stream",
                "--nav-origin",
                "42.0957,-88.0340,200",
                "--no-status",
                "--position-port",
                "0",
                "--first-nav-timeout",
                "30",
                "--pose-log",
                poses,
                "--nav-record",
                rec},
               live_out);
    ASSERT_TRUE(eventually(
        [&] {
            return slurp(live_out).find("waiting for navigation") != std::string::npos ||
                   !live.running();
        },
        std::chrono::seconds(60)))
        << slurp(live_out);
    ASSERT_TRUE(live.running()) << slurp(live_out);
    std::ofstream(tmp.file("go")) << "go\n";  // the stand-in answers OK: gpsfake starts playing

    const int fake_rc = gpsfake.wait_until(Clock::now() + std::chrono::seconds(40));
    const std::string fake_text = slurp(tmp.file("gpsfake.out"));
    ASSERT_GE(fake_rc, 0) << "gpsfake still running after 40 s: " << fake_text;
    live.signal(SIGINT);
    const int live_rc = live.wait_until(Clock::now() + std::chrono::seconds(20));
    const std::string out = slurp(live_out);
    ASSERT_EQ(live_rc, 0) << out << "\ngpsfake (exit " << fake_rc << "): " << fake_text;
    std::printf("gpsfake exit %d: %s%s", fake_rc, fake_text.c_str(), out.c_str());

    // Every sentence gpsfake wrote reached live: the raw capture holds them in order.
    const std::string raw = slurp(rec);
    std::size_t at = 0, found = 0;
    for (const auto& s : sentences) {
        const std::size_t p = raw.find(s, at);
        if (p == std::string::npos) continue;
        ++found;
        at = p + s.size();
    }
    EXPECT_EQ(found, sentences.size()) << "raw capture " << raw.size() << " bytes";

    // The pose log: positions = the GGA positions mapped through the same frame; headings =
    // PASHR; times = the log's UTC on its date, in GPS time.
    const navpose::NavFrame frame = navpose::NavFrame::tangent_plane(42.0957, -88.0340, 200);
    std::size_t ip = 0, ia = 0;
    double worst_pos = 0, worst_head = 0, worst_q_head = 0;
    std::int64_t worst_dt = 0;
    std::vector<std::string> rows = split(slurp(poses), '\n');
    ASSERT_FALSE(rows.empty());
    EXPECT_EQ(rows[0].rfind("gps_time_s,kind,", 0), 0u);
    for (std::size_t r = 1; r < rows.size(); ++r) {
        if (rows[r].empty()) continue;
        const auto c = split(rows[r], ',');
        ASSERT_EQ(c.size(), 16u) << rows[r];
        const core::GpsTime t(*core::parse_decimal_seconds(c[0]));
        if (c[1] == "position") {
            ASSERT_LT(ip, gga.size()) << rows[r];
            const Expected& e = gga[ip++];
            const Eigen::Vector3d want = frame.local_from_geodetic(e.lat, e.lon, e.h);
            const Eigen::Vector3d got(std::stod(c[2]), std::stod(c[3]), std::stod(c[4]));
            worst_pos = std::max(worst_pos, (got - want).norm());
            worst_dt = std::max(worst_dt, std::abs((t - e.t).count()));
            EXPECT_EQ(c[12], "msl");
        } else {
            ASSERT_EQ(c[1], "attitude");
            ASSERT_LT(ia, pashr.size()) << rows[r];
            const Expected& e = pashr[ia++];
            worst_dt = std::max(worst_dt, std::abs((t - e.t).count()));
            worst_head = std::max(worst_head, std::abs(std::stod(c[15]) - e.heading_deg));
            const Eigen::Quaterniond q(std::stod(c[5]), std::stod(c[6]), std::stod(c[7]),
                                       std::stod(c[8]));
            const Eigen::Vector3d g = frame.geodetic_from_local(Eigen::Vector3d::Zero());
            const double h = frame.ned_euler(q, g.x(), g.y()).z() * 180 / M_PI;
            worst_q_head = std::max(worst_q_head, std::abs(h - e.heading_deg));
        }
    }
    std::printf(
        "[ gpsfake rst39 ] %zu positions, %zu attitudes; worst position error %.6f mm, "
        "heading %.6f deg (CSV) %.6f deg (local attitude), time %lld ns; headings "
        "%.2f -> %.2f deg\n",
        ip, ia, worst_pos * 1e3, worst_head, worst_q_head, static_cast<long long>(worst_dt),
        pashr.front().heading_deg, pashr.back().heading_deg);
    EXPECT_EQ(ip, gga.size());
    EXPECT_EQ(ia, pashr.size());
    EXPECT_LT(worst_pos, 1e-3);
    EXPECT_LT(worst_head, 0.01);
    EXPECT_LT(worst_q_head, 0.01);
    EXPECT_EQ(worst_dt, 0);

    std::smatch m;
    ASSERT_TRUE(std::regex_search(out, m, std::regex("nav samples ([0-9]+) applied ([0-9]+)")))
        << out;
    EXPECT_EQ(std::stoull(m[2].str()), gga.size() + pashr.size());
    EXPECT_NE(out.find("decode rejected 0 "), std::string::npos) << out;
    EXPECT_NE(out.find("pose rejected 0 "), std::string::npos) << out;
    EXPECT_NE(out.find("pose log: 139 samples"), std::string::npos) << out;
}

}  // namespace
}  // namespace mirage::test
