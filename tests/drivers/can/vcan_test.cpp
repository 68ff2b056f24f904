// SPDX-License-Identifier: Apache-2.0
// SocketCanBus against a real kernel CAN stack: vcan interfaces inside the qemu VM of
// scripts/vm-can (docs/nav-protocols.md §13.4), with can-utils' candump and cansend as the peer.
// Outside the VM (MIRAGE_VCAN unset) every test skips with a visible reason.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <ctime>
#include <sstream>
#include <string>
#include <vector>

#include "mirage/can/socketcan_bus.hpp"
#include "mirage/core/error.hpp"

extern char** environ;

namespace {

using mirage::can::CanBus;
using mirage::can::RxStatus;
using mirage::nav::CanFrame;
using namespace std::chrono_literals;

std::string env_or_empty(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

#define VCAN_OR_SKIP(var, env)                 \
    const std::string var = env_or_empty(env); \
    if (var.empty())                           \
    GTEST_SKIP() << env << " not set: runs inside the CAN VM (ctest -L vm, scripts/vm-can)"

std::int64_t now_ns() {
    timespec ts{};
    ::clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// A child process (can-utils, ip), optionally with its stdout on a pipe read line by line.
class Child {
  public:
    explicit Child(const std::vector<std::string>& args, bool capture = false) {
        std::vector<char*> argv;
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        posix_spawn_file_actions_t fa;
        posix_spawn_file_actions_init(&fa);
        int fds[2] = {-1, -1};
        if (capture && ::pipe(fds) == 0) {
            posix_spawn_file_actions_adddup2(&fa, fds[1], 1);
            posix_spawn_file_actions_addclose(&fa, fds[0]);
            posix_spawn_file_actions_addclose(&fa, fds[1]);
        }
        if (::posix_spawnp(&pid_, argv[0], &fa, nullptr, argv.data(), environ) != 0) pid_ = -1;
        posix_spawn_file_actions_destroy(&fa);
        if (fds[1] >= 0) ::close(fds[1]);
        out_ = fds[0];
    }
    ~Child() {
        if (pid_ > 0) {
            ::kill(pid_, SIGTERM);
            wait();
        }
        if (out_ >= 0) ::close(out_);
    }
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

    bool started() const { return pid_ > 0; }
    // Exit status, or -1 when it did not exit normally.
    int wait() {
        int status = 0;
        if (pid_ <= 0 || ::waitpid(pid_, &status, 0) != pid_) return -1;
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    // The next stdout line, or false when none arrives within `timeout`.
    bool read_line(std::string& line, std::chrono::milliseconds timeout) {
        const std::int64_t deadline = now_ns() + timeout.count() * 1'000'000;
        for (;;) {
            const auto nl = buf_.find('\n');
            if (nl != std::string::npos) {
                line = buf_.substr(0, nl);
                buf_.erase(0, nl + 1);
                return true;
            }
            const std::int64_t left_ms = (deadline - now_ns()) / 1'000'000;
            if (left_ms <= 0 || out_ < 0) return false;
            pollfd pfd{out_, POLLIN, 0};
            if (::poll(&pfd, 1, static_cast<int>(left_ms)) <= 0) return false;
            char chunk[512];
            const ssize_t n = ::read(out_, chunk, sizeof chunk);
            if (n <= 0) return false;
            buf_.append(chunk, static_cast<std::size_t>(n));
        }
    }

  private:
    pid_t pid_ = -1;
    int out_ = -1;
    std::string buf_;
};

int run(const std::vector<std::string>& args) {
    Child c(args);
    return c.started() ? c.wait() : -1;
}

CanFrame make(std::uint32_t id, bool extended, std::vector<std::uint8_t> bytes, bool rtr = false) {
    CanFrame f;
    f.id = id;
    f.extended = extended;
    f.rtr = rtr;
    f.len = static_cast<std::uint8_t>(bytes.size());
    for (std::size_t i = 0; i < bytes.size(); ++i) f.data[i] = bytes[i];
    if (rtr) f.data = {};
    return f;
}

// docs/nav-protocols.md §7.1: OxTS HeadingPitchRoll for heading 84.40°, pitch 1.20°, roll −0.50°.
const CanFrame kOxts607 = make(0x607, false, {0xF8, 0x20, 0x78, 0x00, 0xCE, 0xFF});
const CanFrame kExt = make(0x18FF50E5, true, {0xAA, 0xBB, 0xCC, 0xDD, 0x11, 0x22, 0x33, 0x44});
const CanFrame kRtr = make(0x123, false, {}, true);
const CanFrame kEmpty = make(0x100, false, {});

// Intel-order fields of 0x607 (§7.1): U16 heading, S16 pitch, S16 roll, × 0.01°.
void expect_oxts_hpr(const CanFrame& f) {
    const auto u16 = [&](int i) {
        return static_cast<std::uint16_t>(f.data[static_cast<std::size_t>(i)] |
                                          (f.data[static_cast<std::size_t>(i + 1)] << 8));
    };
    EXPECT_DOUBLE_EQ(u16(0) * 0.01, 84.40);
    EXPECT_DOUBLE_EQ(static_cast<std::int16_t>(u16(2)) * 0.01, 1.20);
    EXPECT_DOUBLE_EQ(static_cast<std::int16_t>(u16(4)) * 0.01, -0.50);
}

// The frame part of a `candump -L` line "(1700000000.123456) vcan0 607#F8207800CEFF".
std::string frame_text(const std::string& line) {
    std::istringstream in(line);
    std::string stamp, ifname, frame;
    in >> stamp >> ifname >> frame;
    return frame;
}

TEST(SocketCanVcan, frames_sent_by_the_bus_are_logged_by_candump) {
    VCAN_OR_SKIP(ifname, "MIRAGE_VCAN");
    auto bus = mirage::can::open_socketcan(ifname);
    Child candump({"candump", "-L", ifname}, true);
    ASSERT_TRUE(candump.started());
    // candump binds its socket some time after it starts: send probe frames (0x7FF) until one
    // shows up, so the frames under test cannot be sent before it listens.
    const CanFrame probe = make(0x7FF, false, {0x01});
    std::string line;
    bool ready = false;
    for (int i = 0; i < 500 && !ready; ++i) {
        ASSERT_TRUE(bus->send(probe));
        ready = candump.read_line(line, 20ms);
    }
    ASSERT_TRUE(ready) << "candump never logged a probe frame";

    for (const CanFrame& f : {kOxts607, kExt, kRtr, kEmpty}) ASSERT_TRUE(bus->send(f));
    ASSERT_TRUE(bus->send(make(0x7FE, false, {0xEE})));  // end marker

    std::vector<std::string> seen;
    while (candump.read_line(line, 5000ms)) {
        const std::string f = frame_text(line);
        std::printf("candump: %s\n", line.c_str());
        if (f.rfind("7FF#", 0) == 0) continue;  // late probes
        if (f == "7FE#EE") break;
        seen.push_back(f);
    }
    const std::vector<std::string> expected = {"607#F8207800CEFF", "18FF50E5#AABBCCDD11223344",
                                               "123#R", "100#"};
    EXPECT_EQ(seen, expected);
    EXPECT_EQ(line.find(" " + ifname + " ") != std::string::npos, true) << line;
    EXPECT_EQ(bus->counters().tx_failed, 0u);
    EXPECT_GE(bus->counters().tx_frames, 6u);
}

TEST(SocketCanVcan, frames_sent_by_cansend_are_received_with_flags_and_data) {
    VCAN_OR_SKIP(ifname, "MIRAGE_VCAN");
    auto bus = mirage::can::open_socketcan(ifname);
    EXPECT_EQ(bus->name(), "socketcan:" + ifname);
    const struct {
        const char* text;
        CanFrame frame;
    } cases[] = {{"607#F8207800CEFF", kOxts607},
                 {"18FF50E5#AABBCCDD11223344", kExt},
                 {"123#R", kRtr},
                 {"100#", kEmpty}};
    for (const auto& c : cases) {
        const std::int64_t before = now_ns();
        ASSERT_EQ(run({"cansend", ifname, c.text}), 0) << c.text;
        CanFrame got;
        std::int64_t host_ns = 0;
        ASSERT_EQ(bus->receive(got, host_ns, 5s), RxStatus::Frame) << c.text;
        EXPECT_EQ(got, c.frame) << c.text;
        // host_ns is CLOCK_MONOTONIC at read time: after the send started, not in the future.
        EXPECT_GE(host_ns, before);
        EXPECT_LE(host_ns, now_ns());
        if (c.frame.id == 0x607) expect_oxts_hpr(got);
    }
    CanFrame none;
    std::int64_t t = 0;
    EXPECT_EQ(bus->receive(none, t, 0ns), RxStatus::Timeout);
    EXPECT_EQ(bus->receive(none, t, 20ms), RxStatus::Timeout);
    EXPECT_EQ(bus->counters().rx_frames, 4u);
    EXPECT_EQ(bus->counters().malformed, 0u);
    std::printf("received 4 frames from cansend on %s; OxTS 0x607 heading 84.40 deg\n",
                ifname.c_str());
}

TEST(SocketCanVcan, oxts_607_round_trips_between_two_buses_without_echo_to_the_sender) {
    VCAN_OR_SKIP(ifname, "MIRAGE_VCAN");
    auto tx = mirage::can::open_socketcan(ifname);
    auto rx = mirage::can::open_socketcan(ifname);
    ASSERT_TRUE(tx->send(kOxts607));
    CanFrame got;
    std::int64_t t = 0;
    ASSERT_EQ(rx->receive(got, t, 5s), RxStatus::Frame);
    EXPECT_EQ(got, kOxts607);
    expect_oxts_hpr(got);
    // The kernel loops frames back to other sockets only (CAN_RAW_RECV_OWN_MSGS is off).
    EXPECT_EQ(tx->receive(got, t, 0ns), RxStatus::Timeout);
    EXPECT_EQ(tx->counters().tx_frames, 1u);
    EXPECT_EQ(rx->counters().rx_frames, 1u);
}

TEST(SocketCanVcan, error_frames_pass_the_error_filter_and_bus_off_is_counted) {
    VCAN_OR_SKIP(ifname, "MIRAGE_VCAN");
    auto bus = mirage::can::open_socketcan(ifname);
    // An 8-digit id with CAN_ERR_FLAG (0x20000000) is an error frame for cansend (§8);
    // 0x40 = CAN_ERR_BUSOFF, 0x04 = CAN_ERR_CRTL with data[1] = 0x20 (CAN_ERR_CRTL_TX_PASSIVE).
    // The kernel delivers error frames only to sockets that set CAN_RAW_ERR_FILTER.
    ASSERT_EQ(run({"cansend", ifname, "20000040#0000000000000000"}), 0);
    ASSERT_EQ(run({"cansend", ifname, "20000004#0020000000000000"}), 0);
    ASSERT_EQ(run({"cansend", ifname, "607#F8207800CEFF"}), 0);
    CanFrame got;
    std::int64_t t = 0;
    ASSERT_EQ(bus->receive(got, t, 5s), RxStatus::ErrorFrame);
    EXPECT_TRUE(got.error);
    EXPECT_EQ(got.id, 0x40u);
    EXPECT_EQ(got.len, 8u);
    ASSERT_EQ(bus->receive(got, t, 5s), RxStatus::ErrorFrame);
    EXPECT_EQ(got.id, 0x04u);
    EXPECT_EQ(got.data[1], 0x20u);
    ASSERT_EQ(bus->receive(got, t, 5s), RxStatus::Frame);
    EXPECT_EQ(got, kOxts607);
    const auto c = bus->counters();
    EXPECT_EQ(c.error_frames, 2u);
    EXPECT_EQ(c.bus_off, 1u);
    EXPECT_EQ(c.rx_frames, 1u);
}

TEST(SocketCanVcan, frames_the_bus_cannot_carry_are_refused_and_counted) {
    VCAN_OR_SKIP(ifname, "MIRAGE_VCAN");
    auto bus = mirage::can::open_socketcan(ifname);
    CanFrame too_long = kOxts607;
    too_long.len = 9;
    CanFrame wide_std = kOxts607;
    wide_std.id = 0x800;
    CanFrame wide_ext = kExt;
    wide_ext.id = 0x20000000;
    CanFrame err = kOxts607;
    err.error = true;
    EXPECT_FALSE(bus->send(too_long));
    EXPECT_FALSE(bus->send(wide_std));
    EXPECT_FALSE(bus->send(wide_ext));
    EXPECT_FALSE(bus->send(err));
    EXPECT_EQ(bus->counters().tx_failed, 4u);
    EXPECT_EQ(bus->counters().tx_frames, 0u);
}

TEST(SocketCanVcan, interface_down_or_removed_reports_closed_and_failed_sends) {
    VCAN_OR_SKIP(ifname, "MIRAGE_VCAN_SPARE");
    auto bus = mirage::can::open_socketcan(ifname);
    CanFrame got;
    std::int64_t t = 0;

    ASSERT_EQ(run({"ip", "link", "set", ifname, "down"}), 0);
    EXPECT_EQ(bus->receive(got, t, 5s), RxStatus::Closed);  // ENETDOWN
    EXPECT_FALSE(bus->send(kOxts607));
    EXPECT_EQ(bus->counters().tx_failed, 1u);

    ASSERT_EQ(run({"ip", "link", "set", ifname, "up"}), 0);
    EXPECT_TRUE(bus->send(kOxts607));  // the binding survives down/up

    ASSERT_EQ(run({"ip", "link", "delete", ifname}), 0);
    EXPECT_EQ(bus->receive(got, t, 5s), RxStatus::Closed);  // ENODEV, socket unbound
    EXPECT_FALSE(bus->send(kOxts607));
    EXPECT_EQ(bus->counters().tx_failed, 2u);
    EXPECT_EQ(bus->counters().tx_frames, 1u);

    try {
        (void)mirage::can::open_socketcan(ifname);
        ADD_FAILURE() << "reopening a deleted interface did not throw";
    } catch (const mirage::IoError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "socketcan '" + ifname + "': no such interface: No such device (ENODEV)");
    }
}

}  // namespace
