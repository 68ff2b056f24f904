// SPDX-License-Identifier: Apache-2.0
// `mirage record` onto a disk that fills up: a 64 KiB tmpfs in a private mount namespace (forked
// child, root only; skipped visibly otherwise). The recorder stops with an error naming the cause
// and leaves a valid pcap of whole records only, every one of them readable.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sched.h>
#include <sys/mount.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "mirage/pcap/pcap.hpp"
#include "mirage/replay/recorder.hpp"
#include "test_paths.hpp"

namespace {

using namespace mirage;
using namespace std::chrono_literals;

constexpr std::size_t kPayload = 1000;
constexpr std::size_t kRecord = 16 + 14 + 20 + 8 + kPayload;  // pcap header + Ethernet/IPv4/UDP

// Exit codes: 0 passed, 77 no private mount namespace / tmpfs, others = the failed check.
int full_disk_child(const std::string& dir) {
    if (::unshare(CLONE_NEWNS) != 0) return 77;
    if (::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) return 77;
    if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64k") != 0) return 77;
    replay::RecordConfig rc;
    rc.ports = {0};
    rc.bind_host = "127.0.0.1";
    rc.out = dir + "/rec.pcap";
    rc.flush_interval_ns = 5'000'000;
    replay::Recorder rec(rc);
    std::atomic<bool> stop{false};
    replay::RecordResult result;
    std::atomic<bool> done{false};
    std::thread t([&] {
        result = rec.run(stop);
        done = true;
    });
    const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(rec.ports()[0]);
    ::inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
    std::vector<std::uint8_t> payload(kPayload, 0x5A);
    // 64 KiB hold 60 records: send up to 400 (in small groups, so the receive buffer keeps up)
    // until the recorder gives up on the full disk; deadline 10 s.
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    for (int i = 0; i < 400 && !done && std::chrono::steady_clock::now() < deadline; ++i) {
        ::sendto(s, payload.data(), payload.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
        if (i % 10 == 9) std::this_thread::sleep_for(2ms);
    }
    while (!done && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(5ms);
    stop = true;
    t.join();
    ::close(s);
    if (result.error.find("No space left") == std::string::npos) return 10;
    std::error_code ec;
    const auto size = std::filesystem::file_size(rc.out, ec);
    if (ec || size != result.file_bytes) return 11;
    if ((size - 24) % kRecord != 0 || size < 24 + kRecord) return 12;  // whole records only
    pcap::Reader r(rc.out);
    pcap::UdpDatagram d;
    std::uint64_t n = 0;
    while (r.next(d)) {
        if (d.payload != payload) return 13;
        ++n;
    }
    if (!r.error().empty()) return 14;
    if (n != (size - 24) / kRecord) return 15;
    std::printf("full disk: stopped with '%s'; file %llu bytes = %llu whole records, all read\n",
                result.error.c_str(), static_cast<unsigned long long>(size),
                static_cast<unsigned long long>(n));
    std::fflush(stdout);
    return 0;
}

TEST(RecordFullDisk, stops_with_a_clear_error_and_leaves_whole_records_only) {
    test::TempDir dir;
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) ::_exit(full_disk_child(dir.path().string()));
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    if (WEXITSTATUS(status) == 77)
        GTEST_SKIP() << "no private mount namespace or tmpfs (not root?)";
    EXPECT_EQ(WEXITSTATUS(status), 0) << "failed check code in full_disk_child()";
}

}  // namespace
