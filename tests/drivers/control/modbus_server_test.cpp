// SPDX-License-Identifier: Apache-2.0
#include "mirage/control/modbus_server.hpp"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "mirage/core/error.hpp"

namespace mirage::control {
namespace {

using Clock = std::chrono::steady_clock;

Identity ident() {
    Identity id;
    id.version[0] = 0;
    id.version[1] = 9;
    id.rig_hash = 0xFEEDFACECAFEBEEFull;
    id.scenarios = 2;
    id.sensors = 2;
    return id;
}

struct Fixture {
    ControlModel model{ident(), {}, 0};
    std::unique_ptr<ModbusServer> server;
    explicit Fixture(ControlEndpoint ep = {}) {
        if (ep.tcp_port == 1502) ep.tcp_port = 0;
        server = std::make_unique<ModbusServer>(ep, model, [] {
            RigStatus s;
            s.sim_time_ns = 42;
            s.sensors.resize(2);
            s.sensors[0].packets = 1234;
            return s;
        });
        server->start();
    }
};

struct ClientDeleter {
    void operator()(modbus_t* c) const {
        modbus_close(c);
        modbus_free(c);
    }
};
using ClientPtr = std::unique_ptr<modbus_t, ClientDeleter>;

ClientPtr tcp_client(int port) {
    ClientPtr c(modbus_new_tcp("127.0.0.1", port));
    EXPECT_EQ(modbus_connect(c.get()), 0) << modbus_strerror(errno);
    return c;
}

int raw_connect(int port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
    EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
    return fd;
}

// Reads one reply with a 2 s deadline; empty when the server closed the connection.
std::vector<std::uint8_t> raw_reply(int fd) {
    std::vector<std::uint8_t> r(260);
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 2000) <= 0) return {};
    const ssize_t n = ::recv(fd, r.data(), r.size(), 0);
    r.resize(n > 0 ? std::size_t(n) : 0);
    return r;
}

std::vector<std::uint8_t> mbap(std::uint16_t tid, std::vector<std::uint8_t> pdu) {
    std::vector<std::uint8_t> f(7 + pdu.size());
    f[0] = std::uint8_t(tid >> 8);
    f[1] = std::uint8_t(tid);
    f[4] = std::uint8_t((pdu.size() + 1) >> 8);
    f[5] = std::uint8_t(pdu.size() + 1);
    f[6] = 1;
    for (std::size_t i = 0; i < pdu.size(); ++i) f[7 + i] = pdu[i];
    return f;
}

void send_all(int fd, const std::vector<std::uint8_t>& b) {
    ASSERT_EQ(::send(fd, b.data(), b.size(), MSG_NOSIGNAL), ssize_t(b.size()));
}

TEST(ModbusServer, TcpClientReadsIdentityAndDrivesTheStateMachine) {
    Fixture f;
    auto c = tcp_client(f.server->tcp_port());
    std::array<std::uint16_t, 24> in{};
    ASSERT_EQ(modbus_read_input_registers(c.get(), 0, 24, in.data()), 24);
    EXPECT_EQ(in[ir::kProduct], kProductId);
    EXPECT_EQ(in[ir::kVersion + 1], 9);
    EXPECT_EQ(in[ir::kRigHash], 0xFEED);
    EXPECT_EQ(in[ir::kRigHash + 3], 0xBEEF);
    EXPECT_EQ(in[ir::kState], 0);
    EXPECT_EQ(in[ir::kSimTime + 3], 42);
    std::array<std::uint16_t, 2> pk{};
    ASSERT_EQ(modbus_read_input_registers(c.get(), ir::kSensorBase + ir::kPackets, 2, pk.data()),
              2);
    EXPECT_EQ(pk[1], 1234);
    // Start before arm: server busy, and nothing changed.
    EXPECT_EQ(modbus_write_register(c.get(), hr::kCommand, 2), -1);
    EXPECT_EQ(errno, EMBXSBUSY);
    EXPECT_EQ(f.model.state(), RigState::Idle);
    ASSERT_EQ(modbus_write_register(c.get(), hr::kCommand, 1), 1);
    ASSERT_EQ(modbus_write_register(c.get(), hr::kCommand, 2), 1);
    EXPECT_EQ(f.model.state(), RigState::Running);
    // A fault block in one request; one bad value refuses all of it.
    const std::array<std::uint16_t, 2> bad{100, 0};
    EXPECT_EQ(modbus_write_registers(c.get(), hr::kFaultBase, 2, bad.data()), -1);
    EXPECT_EQ(errno, EMBXILVAL);
    const std::array<std::uint16_t, 7> block{500, 3, 0, 200, 0, 0, 0};
    ASSERT_EQ(modbus_write_registers(c.get(), hr::kFaultBase + hr::kFaultStride, 7, block.data()),
              7);
    EXPECT_EQ(f.model.faults(1).load().range_bias_mm, 200);
    std::array<std::uint16_t, 7> back{};
    ASSERT_EQ(modbus_read_registers(c.get(), hr::kFaultBase + hr::kFaultStride, 7, back.data()), 7);
    EXPECT_EQ(back, block);
    // Out of the window: illegal address.
    EXPECT_EQ(modbus_read_input_registers(c.get(), 139, 2, in.data()), -1);
    EXPECT_EQ(errno, EMBXILADD);
    ASSERT_EQ(modbus_write_register(c.get(), hr::kCommand, 3), 1);
    EXPECT_EQ(f.model.state(), RigState::Stopped);
}

TEST(ModbusServer, MisbehavingClientsLeaveItAnswering) {
    ControlEndpoint ep;
    ep.max_clients = 4;
    Fixture f(ep);
    const int port = f.server->tcp_port();
    auto good = tcp_client(port);
    std::uint16_t v = 0;
    const auto still_answers = [&] {
        return modbus_read_input_registers(good.get(), ir::kProduct, 1, &v) == 1 && v == kProductId;
    };
    // Half a frame, then silence: others are answered meanwhile; the rest completes it.
    const int partial = raw_connect(port);
    const auto req = mbap(7, {0x04, 0x00, 0x00, 0x00, 0x01});
    send_all(partial, {req.begin(), req.begin() + 4});
    EXPECT_TRUE(still_answers());
    send_all(partial, {req.begin() + 4, req.end()});
    auto r = raw_reply(partial);
    ASSERT_EQ(r.size(), 11u);
    EXPECT_EQ(r[1], 7);  // transaction id echoed
    EXPECT_EQ(r[10], kProductId & 0xFF);
    // A function libmodbus does not know, framed correctly: exception 01, connection kept.
    send_all(partial, mbap(8, {0x2B, 0x0E, 0x01, 0x00}));
    r = raw_reply(partial);
    ASSERT_EQ(r.size(), 9u);
    EXPECT_EQ(r[7], 0x2B | 0x80);
    EXPECT_EQ(r[8], 1);
    // Count and byte count disagree (FC 16): exception 03, nothing written.
    send_all(partial, mbap(9, {0x10, 0x00, 0x64, 0x00, 0x03, 0x04, 0x01, 0xF4, 0x00, 0x01}));
    r = raw_reply(partial);
    ASSERT_EQ(r.size(), 9u);
    EXPECT_EQ(r[8], 3);
    EXPECT_EQ(f.model.faults(0).load(), FaultSettings{});
    // Short FC 07 and FC 11 (libmodbus has read past them): exception 01.
    send_all(partial, mbap(10, {0x07}));
    r = raw_reply(partial);
    ASSERT_EQ(r.size(), 9u);
    EXPECT_EQ(r[8], 1);
    // A flood of pipelined requests: every one answered, in order.
    std::vector<std::uint8_t> flood;
    for (std::uint16_t t = 0; t < 500; ++t) {
        const auto q = mbap(t, {0x03, 0x00, 0x00, 0x00, 0x04});
        flood.insert(flood.end(), q.begin(), q.end());
    }
    send_all(partial, flood);
    std::size_t got = 0;
    std::vector<std::uint8_t> all;
    while (all.size() < 500 * 17) {
        auto part = raw_reply(partial);
        if (part.empty()) break;
        all.insert(all.end(), part.begin(), part.end());
    }
    got = all.size() / 17;
    EXPECT_EQ(got, 500u);
    EXPECT_TRUE(still_answers());
    // A bad protocol id: that connection is closed, the others are not.
    const int liar = raw_connect(port);
    auto lie = mbap(1, {0x04, 0x00, 0x00, 0x00, 0x01});
    lie[2] = 0x12;
    send_all(liar, lie);
    EXPECT_TRUE(raw_reply(liar).empty());
    EXPECT_TRUE(still_answers());
    // More connections than allowed: the extra ones are closed at once, counted.
    std::vector<int> extra;
    for (int i = 0; i < 6; ++i) extra.push_back(raw_connect(port));
    for (int fd : extra) {
        send_all(fd, mbap(1, {0x04, 0x00, 0x00, 0x00, 0x01}));
    }
    int answered = 0;
    for (int fd : extra) answered += raw_reply(fd).size() == 11u;
    EXPECT_EQ(answered, 2);  // good and partial hold two of the four places
    EXPECT_TRUE(still_answers());
    const ServerCounters sc = f.server->counters();
    EXPECT_EQ(sc.refused_connections, 4u);
    EXPECT_EQ(sc.closed_malformed, 1u);
    for (int fd : extra) ::close(fd);
    ::close(liar);
    ::close(partial);
}

// A linked pty pair from socat; the server on one end, the client on the other.
struct PtyPair {
    pid_t pid = -1;
    std::string a, b;
    explicit PtyPair(const std::string& dir) : a(dir + "/a"), b(dir + "/b") { start(); }
    void start() {
        pid = ::fork();
        if (pid == 0) {
            const std::string l = "pty,raw,echo=0,link=" + a, r = "pty,raw,echo=0,link=" + b;
            ::execlp("socat", "socat", l.c_str(), r.c_str(), static_cast<char*>(nullptr));
            std::_Exit(127);
        }
        const auto deadline = Clock::now() + std::chrono::seconds(5);
        while (Clock::now() < deadline &&
               !(std::filesystem::exists(a) && std::filesystem::exists(b)))
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    void kill() {
        if (pid > 0) {
            ::kill(pid, SIGTERM);
            ::waitpid(pid, nullptr, 0);
            pid = -1;
        }
    }
    ~PtyPair() { kill(); }
};

bool have_socat() { return std::system("command -v socat >/dev/null 2>&1") == 0; }

ClientPtr rtu_client(const std::string& dev) {
    ClientPtr c(modbus_new_rtu(dev.c_str(), 115200, 'N', 8, 1));
    modbus_set_slave(c.get(), 1);
    modbus_set_response_timeout(c.get(), 1, 0);
    EXPECT_EQ(modbus_connect(c.get()), 0) << dev << ": " << modbus_strerror(errno);
    return c;
}

TEST(ModbusServer, RtuOverAPtyServesAndReopensAVanishedLine) {
    if (!have_socat()) GTEST_SKIP() << "socat not installed (scripts/install-deps)";
    const std::string dir = ::testing::TempDir() + "/mirage_rtu_" + std::to_string(::getpid());
    std::filesystem::create_directories(dir);
    PtyPair pty(dir);
    ASSERT_TRUE(std::filesystem::exists(pty.a));
    ControlEndpoint ep;
    ep.tcp_port = -1;
    ep.rtu_device = pty.a;
    Fixture f(ep);
    {
        auto c = rtu_client(pty.b);
        std::uint16_t v = 0;
        ASSERT_EQ(modbus_read_input_registers(c.get(), ir::kProduct, 1, &v), 1)
            << modbus_strerror(errno);
        EXPECT_EQ(v, kProductId);
        ASSERT_EQ(modbus_write_register(c.get(), hr::kCommand, 1), 1);
        EXPECT_EQ(f.model.state(), RigState::Armed);
        // A frame with a bad CRC is counted and dropped.
        const std::uint8_t junk[] = {0x01, 0x04, 0x00, 0x00, 0x00, 0x01, 0xDE, 0xAD};
        ASSERT_EQ(::write(modbus_get_socket(c.get()), junk, sizeof junk), ssize_t(sizeof junk));
        std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the frame gap
        modbus_flush(c.get());
        ASSERT_EQ(modbus_read_input_registers(c.get(), ir::kState, 1, &v), 1)
            << modbus_strerror(errno);
        EXPECT_EQ(v, 1);
        EXPECT_GE(f.server->counters().frame_errors, 1u);
        // Another unit's request is not answered (libmodbus then ignores the next frame on the
        // bus as that unit's reply).
        modbus_set_slave(c.get(), 7);
        modbus_set_response_timeout(c.get(), 0, 200'000);
        EXPECT_EQ(modbus_read_input_registers(c.get(), 0, 1, &v), -1);
    }
    // The line vanishes (adapter unplugged) and comes back: reopened, answering again.
    pty.kill();
    const auto lost_by = Clock::now() + std::chrono::seconds(3);
    while (Clock::now() < lost_by && f.server->counters().rtu_open)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_FALSE(f.server->counters().rtu_open);
    pty.start();
    const auto back_by = Clock::now() + std::chrono::seconds(10);
    while (Clock::now() < back_by && !f.server->counters().rtu_open)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_TRUE(f.server->counters().rtu_open);
    EXPECT_GE(f.server->counters().rtu_reopens, 1u);
    auto c = rtu_client(pty.b);
    std::uint16_t v = 0;
    ASSERT_EQ(modbus_read_input_registers(c.get(), ir::kState, 1, &v), 1) << modbus_strerror(errno);
    EXPECT_EQ(v, 1);
    std::filesystem::remove_all(dir);
}

// A client that pipelines reads of 125 input registers and never reads the replies: once its socket
// buffers are full the server closes it (counted) instead of blocking, answers another client
// meanwhile, and stops promptly. A status callback that throws is exception 04, not a crash.
TEST(ModbusServer, AClientThatNeverReadsIsClosedNotWaitedFor) {
    ControlEndpoint ep;
    ep.tcp_port = 0;
    ControlModel model(ident(), {}, 0);
    bool fail_status = false;
    auto server = std::make_unique<ModbusServer>(ep, model, [&fail_status] {
        if (fail_status) throw std::runtime_error("status unavailable");
        RigStatus s;
        s.sensors.resize(2);
        return s;
    });
    server->start();
    const int fd = raw_connect(server->tcp_port());
    const auto req = mbap(1, {0x04, 0x00, 0x00, 0x00, 125});  // 12 bytes in, 259 out
    std::size_t sent = 0;
    const auto deadline = Clock::now() + std::chrono::seconds(10);
    while (Clock::now() < deadline && server->counters().closed_unread == 0) {
        const ssize_t n = ::send(fd, req.data(), req.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n > 0) {
            sent += std::size_t(n) / req.size();
        } else {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    }
    const ServerCounters c = server->counters();
    std::printf(
        "[ modbus ] a client that never reads: %zu requests sent, closed after %llu "
        "replies\n",
        sent, static_cast<unsigned long long>(c.replies));
    EXPECT_EQ(c.closed_unread, 1u);
    auto other = tcp_client(server->tcp_port());
    std::uint16_t v = 0;
    EXPECT_EQ(modbus_read_input_registers(other.get(), ir::kState, 1, &v), 1)
        << modbus_strerror(errno);
    fail_status = true;
    EXPECT_EQ(modbus_read_input_registers(other.get(), ir::kState, 1, &v), -1);
    EXPECT_EQ(errno, EMBXSFAIL);
    EXPECT_EQ(server->counters().internal_errors, 1u);
    const auto t0 = Clock::now();
    server->stop();
    EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 1.0);
    ::close(fd);
}

TEST(ModbusServer, AnAddressInUseIsAClearError) {
    Fixture f;
    ControlEndpoint ep;
    ep.tcp_port = f.server->tcp_port();
    ControlModel m(ident(), {}, 0);
    try {
        ModbusServer second(ep, m, {});
        FAIL() << "bound twice";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("control: tcp 127.0.0.1:"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("in use"), std::string::npos) << e.what();
    }
    ControlEndpoint p;
    EXPECT_THROW(parse_tcp_address("1502", p), ConfigError);
    EXPECT_THROW(parse_tcp_address("example.org:1502", p), ConfigError);
    EXPECT_THROW(parse_tcp_address("127.0.0.1:70000", p), ConfigError);
    parse_tcp_address("0.0.0.0:502", p);
    EXPECT_EQ(p.tcp_port, 502);
}

}  // namespace
}  // namespace mirage::control
