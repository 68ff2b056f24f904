// SPDX-License-Identifier: Apache-2.0
// Loopback against a real NMEA peer (docs/nav-protocols.md §13.2): our encoder's 1 Hz GGA+RMC+HDT
// go into a pty that gpsd reads; `gpspipe -w` reports TPVs whose lat/lon/alt must equal ours.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mirage/nmea/nmea_encoder.hpp"
#include "nmea_test_util.hpp"
#include "test_paths.hpp"

namespace mirage::nmea {
namespace {

using Clock = std::chrono::steady_clock;
using nav::NavSample;

std::optional<std::string> find_program(const std::string& name) {
    std::string path = std::getenv("PATH") ? std::getenv("PATH") : "";
    path += ":/usr/sbin:/sbin:/usr/local/sbin";
    std::size_t start = 0;
    while (start <= path.size()) {
        const std::size_t end = std::min(path.find(':', start), path.size());
        const std::string cand = path.substr(start, end - start) + "/" + name;
        if (end > start && ::access(cand.c_str(), X_OK) == 0) return cand;
        start = end + 1;
    }
    return std::nullopt;
}

// A TCP port free right now: bind port 0 and read what the kernel chose.
int free_tcp_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    int port = -1;
    if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0) {
        port = ntohs(a.sin_port);
    }
    ::close(fd);
    return port;
}

bool port_accepts(int port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    ::close(fd);
    return ok;
}

// A child process, terminated and reaped by pid when the test ends.
class Child {
  public:
    Child(const std::vector<std::string>& argv, int stdout_fd, const std::string& log) {
        pid_ = ::fork();
        if (pid_ == 0) {
            const int null_in = ::open("/dev/null", O_RDONLY);
            const int err = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
            ::dup2(null_in, 0);
            ::dup2(stdout_fd >= 0 ? stdout_fd : err, 1);
            ::dup2(err, 2);
            std::vector<char*> args;
            for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
            args.push_back(nullptr);
            ::execv(args[0], args.data());
            ::_exit(127);
        }
    }
    ~Child() {
        if (pid_ > 0) {
            ::kill(pid_, SIGTERM);
            int st = 0;
            ::waitpid(pid_, &st, 0);
        }
    }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

  private:
    pid_t pid_ = -1;
};

std::optional<double> json_number(const std::string& line, const std::string& key) {
    const std::string k = "\"" + key + "\":";
    const std::size_t p = line.find(k);
    if (p == std::string::npos) return std::nullopt;
    return std::strtod(line.c_str() + p + k.size(), nullptr);
}

std::string json_string(const std::string& line, const std::string& key) {
    const std::string k = "\"" + key + "\":\"";
    const std::size_t p = line.find(k);
    if (p == std::string::npos) return {};
    const std::size_t e = line.find('"', p + k.size());
    return line.substr(p + k.size(), e - p - k.size());
}

TEST(NmeaGpsdLoopback, gpsd_reports_our_positions) {
    const auto gpsd = find_program("gpsd");
    const auto gpspipe = find_program("gpspipe");
    if (!gpsd || !gpspipe) GTEST_SKIP() << "gpsd/gpspipe not installed (Debian gpsd, gpsd-clients)";
    ::signal(SIGPIPE, SIG_IGN);

    int master = -1, slave = -1;
    char slave_name[256] = {};
    ASSERT_EQ(::openpty(&master, &slave, slave_name, nullptr, nullptr), 0);
    termios tio{};
    ::tcgetattr(slave, &tio);
    ::cfmakeraw(&tio);
    ::tcsetattr(slave, TCSANOW, &tio);
    ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);

    mirage::test::TempDir dir;
    const int port = free_tcp_port();
    ASSERT_GT(port, 0);
    const std::string log = dir.file("gpsd.log");
    Child gpsd_proc({*gpsd, "-N", "-n", "-b", "-S", std::to_string(port), "-F",
                     dir.file("gpsd.sock"), slave_name},
                    -1, log);
    const auto deadline = Clock::now() + std::chrono::seconds(20);
    while (!port_accepts(port)) {
        ASSERT_LT(Clock::now(), deadline) << "gpsd did not listen on port " << port;
        ::poll(nullptr, 0, 20);
    }
    int pipe_fd[2];
    ASSERT_EQ(::pipe(pipe_fd), 0);
    Child pipe_proc({*gpspipe, "-w", "localhost:" + std::to_string(port)}, pipe_fd[1],
                    dir.file("gpspipe.log"));
    ::close(pipe_fd[1]);

    // Known path: 1 Hz epochs from 2024-05-01T12:00:00Z, moving north-east and climbing.
    EncodeOptions o;
    o.geoid_separation_m = 47.123;
    auto epoch = [](int k) {
        NavSample s;
        s.fields =
            NavSample::kTime | NavSample::kPosition | NavSample::kVelocity | NavSample::kHeading;
        s.t =
            core::GpsTime{core::Nanos{test::gps_ns("2024-05-01T12:00:00Z") + k * 1'000'000'000LL}};
        s.lat_deg = 47.123456789 + 1e-4 * k;
        s.lon_deg = -8.987654321 + 2e-4 * k;
        s.height_m = 512.345 + 0.5 * k;
        s.velocity_ned_mps = {11.1, 15.2, 0.0};
        s.heading_rad = test::rad(30.0 + k);
        s.quality = nav::FixQuality::Differential;
        s.satellites = 11;
        return s;
    };

    struct Seen {
        double lat, lon, alt_hae, alt_msl;
    };
    std::map<int, Seen> seen;  // epoch index -> TPV
    std::string buf;
    int k = 0;
    auto next_write = Clock::now();
    while (seen.size() < 4 && Clock::now() < deadline && k < 60) {
        if (Clock::now() >= next_write) {
            const std::string text = encode_epoch(epoch(k++), kGga | kRmc | kHdt, o);
            ASSERT_EQ(::write(master, text.data(), text.size()), static_cast<ssize_t>(text.size()));
            next_write += std::chrono::milliseconds(250);  // faster than real time is fine
        }
        char junk[512];
        while (::read(master, junk, sizeof junk) > 0) {
        }  // gpsd may probe the device; drop it
        pollfd p{pipe_fd[0], POLLIN, 0};
        if (::poll(&p, 1, 50) > 0) {
            char chunk[4096];
            const ssize_t n = ::read(pipe_fd[0], chunk, sizeof chunk);
            if (n <= 0) break;
            buf.append(chunk, static_cast<std::size_t>(n));
            for (std::size_t e; (e = buf.find('\n')) != std::string::npos; buf.erase(0, e + 1)) {
                const std::string line = buf.substr(0, e);
                if (line.find("\"class\":\"TPV\"") == std::string::npos) continue;
                const std::string t = json_string(line, "time");
                const auto lat = json_number(line, "lat"), lon = json_number(line, "lon");
                const auto hae = json_number(line, "altHAE"), msl = json_number(line, "altMSL");
                if (t.rfind("2024-05-01T12:", 0) != 0 || !lat || !lon || !hae || !msl) continue;
                const int idx = std::stoi(t.substr(14, 2)) * 60 + std::stoi(t.substr(17, 2));
                seen[idx] = {*lat, *lon, *hae, *msl};
                std::printf("gpsd TPV %s lat %.9f lon %.9f altHAE %.3f altMSL %.3f\n", t.c_str(),
                            *lat, *lon, *hae, *msl);
            }
        }
    }
    ::close(pipe_fd[0]);
    ::close(master);
    ::close(slave);
    ASSERT_GE(seen.size(), 3u) << "too few TPVs from gpsd before the deadline (log " << log << ")";
    for (const auto& [idx, s] : seen) {
        const NavSample want = epoch(idx);
        EXPECT_NEAR(s.lat, want.lat_deg, 1e-7) << idx;
        EXPECT_NEAR(s.lon, want.lon_deg, 1e-7) << idx;
        EXPECT_NEAR(s.alt_hae, want.height_m, 0.01) << idx;
        EXPECT_NEAR(s.alt_msl, want.height_m - o.geoid_separation_m, 0.01) << idx;
    }
}

}  // namespace
}  // namespace mirage::nmea
