// SPDX-License-Identifier: Apache-2.0
// mirage-udp-timing-rx, the receiver of scripts/bench-replay: its long-capture writer (exact
// times of every copy) and its matching of received datagrams to the capture's schedule (loss,
// duplicates and strangers counted exactly) over loopback.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "mirage/pcap/pcap.hpp"
#include "mirage/pcap/writer.hpp"
#include "test_paths.hpp"

namespace {

using mirage::pcap::Endpoint;

std::vector<std::uint8_t> payload_of(int i) {
    std::vector<std::uint8_t> p(100 + static_cast<std::size_t>(i % 7));
    for (std::size_t k = 0; k < p.size(); ++k) p[k] = static_cast<std::uint8_t>(i * 31 + k * 7);
    p[0] = static_cast<std::uint8_t>(i);
    p[1] = static_cast<std::uint8_t>(i >> 8);
    return p;
}

// A free UDP port on 127.0.0.1 (bound to 0 and released).
std::uint16_t free_port() {
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in sa{};
    sa.sin_family = AF_INET;
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&sa), sizeof sa);
    socklen_t len = sizeof sa;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&sa), &len);
    ::close(fd);
    return ntohs(sa.sin_port);
}

std::string run(const std::string& cmd) {
    std::string out;
    FILE* f = ::popen(cmd.c_str(), "r");
    char buf[512];
    while (f && std::fgets(buf, sizeof buf, f)) out += buf;
    if (f) ::pclose(f);
    return out;
}

TEST(UdpTimingRx, long_capture_repeats_the_short_one_at_span_plus_mean_gap) {
    mirage::test::TempDir dir;
    const Endpoint src{{192, 168, 1, 200}, 2368}, dst{{255, 255, 255, 255}, 2368};
    {
        mirage::pcap::Writer w(dir.file("short.pcap"));
        for (int i = 0; i < 10; ++i)
            w.write(1'000'000'000 + i * 1'000'000LL, src, dst, payload_of(i));
    }
    // span 9 ms + mean gap 1 ms: period 10 ms; 0.05 s -> floor(5) + 1 = 6 copies.
    run(std::string(MIRAGE_RX_EXE) + " --pcap " + dir.file("short.pcap") + " --make-long " +
        dir.file("long.pcap") + " --seconds 0.05");
    const auto d = mirage::pcap::read_udp(dir.file("long.pcap"));
    ASSERT_EQ(d.size(), 60u);
    for (std::size_t n = 0; n < d.size(); ++n) {
        const auto k = static_cast<std::int64_t>(n / 10);
        const int i = static_cast<int>(n % 10);
        EXPECT_EQ(d[n].time_ns, 1'000'000'000 + k * 10'000'000 + i * 1'000'000LL) << n;
        EXPECT_EQ(d[n].payload, payload_of(i)) << n;
        EXPECT_EQ(d[n].dst.port, 2368);
    }
}

TEST(UdpTimingRx, counts_lost_duplicate_and_stranger_datagrams_exactly) {
    mirage::test::TempDir dir;
    const std::uint16_t port = free_port();
    const Endpoint src{{127, 0, 0, 1}, 40000}, dst{{127, 0, 0, 1}, port};
    {
        mirage::pcap::Writer w(dir.file("sched.pcap"));
        for (int i = 0; i < 50; ++i) w.write(i * 1'000'000LL, src, dst, payload_of(i));
    }
    const std::string ready = dir.file("ready"), json = dir.file("out.json");
    std::string out;
    std::thread rx([&] {
        out = run(std::string(MIRAGE_RX_EXE) + " --pcap " + dir.file("sched.pcap") +
                  " --bind 127.0.0.1 --idle 0.5 --start-timeout 20 --label t --ready " + ready +
                  " --json " + json + " 2>&1");
    });
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!std::filesystem::exists(ready) && std::chrono::steady_clock::now() < give_up)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_TRUE(std::filesystem::exists(ready)) << "receiver never bound";

    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(port);
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    auto send = [&](const std::vector<std::uint8_t>& p) {
        ::sendto(fd, p.data(), p.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
    };
    const std::set<int> dropped{10, 11, 30};
    for (int i = 0; i < 50; ++i) {
        if (dropped.count(i)) continue;
        send(payload_of(i));
        if (i == 5) send(payload_of(5));      // a duplicate
        if (i == 20) send(payload_of(1000));  // not in the capture
    }
    ::close(fd);
    rx.join();
    std::ifstream in(json);
    ASSERT_TRUE(in) << out;
    const auto j = nlohmann::json::parse(in);
    EXPECT_EQ(j["label"], "t");
    EXPECT_EQ(j["scheduled"], 50);
    EXPECT_EQ(j["received"], 49);  // 47 of the schedule + duplicate + stranger
    EXPECT_EQ(j["matched"], 47);
    EXPECT_EQ(j["lost"], 3);
    EXPECT_EQ(j["unmatched"], 2);
    // Anchored on the first packet, whose error is 0 by definition.
    EXPECT_LE(j["err_min_us"].get<double>(), 0.0);
    EXPECT_GE(j["err_max_us"].get<double>(), 0.0);
    // The matched packets span the schedule from packet 0 to packet 49.
    EXPECT_DOUBLE_EQ(j["schedule_span_s"].get<double>(), 0.049);
}

}  // namespace
