// SPDX-License-Identifier: Apache-2.0
// TCP client and UDP streams on the loopback interface, ephemeral ports only.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>

#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "stream_test_util.hpp"

namespace mirage::bytestream {
namespace {

using namespace std::chrono_literals;
using test::bytes_of;
using test::read_exactly;

// A loopback TCP socket on an ephemeral port; `listen` false leaves it bound but refusing.
struct Listener {
    int fd = -1;
    std::uint16_t port = 0;
    explicit Listener(bool listen = true) {
        fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        sockaddr_in sa{};
        sa.sin_family = AF_INET;
        sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        EXPECT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&sa), sizeof sa), 0);
        socklen_t len = sizeof sa;
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&sa), &len);
        port = ntohs(sa.sin_port);
        if (listen) {
            EXPECT_EQ(::listen(fd, 4), 0);
        }
    }
    ~Listener() { ::close(fd); }
    // Accepts with a deadline; -1 on timeout.
    int accept_within(int ms) const {
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, ms) <= 0) return -1;
        return ::accept4(fd, nullptr, nullptr, SOCK_CLOEXEC);
    }
};

// prefix + port without g++ 12's false -Wrestrict on "literal" + std::string&&.
std::string at(std::string prefix, std::uint16_t port) {
    prefix += std::to_string(port);
    return prefix;
}

std::string recv_exactly(int fd, std::size_t want) {
    std::string out;
    char buf[256];
    while (out.size() < want) {
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, 5000) <= 0) break;
        const auto n = ::recv(fd, buf, sizeof buf, 0);
        if (n <= 0) break;
        out.append(buf, static_cast<std::size_t>(n));
    }
    return out;
}

TEST(TcpStream, exchanges_bytes_and_reconnects_after_the_peer_closes) {
    Listener server;
    auto client = open_byte_stream(at("tcp://127.0.0.1:", server.port));
    EXPECT_EQ(client->name(), at("tcp://127.0.0.1:", server.port));
    EXPECT_NE(client->local_port(), 0);
    int peer = server.accept_within(5000);
    ASSERT_GE(peer, 0);

    ASSERT_EQ(::send(peer, "#INSPVAXA", 9, 0), 9);
    EXPECT_EQ(read_exactly(*client, 9), "#INSPVAXA");
    ASSERT_TRUE(client->write(bytes_of("log\r\n")));
    EXPECT_EQ(recv_exactly(peer, 5), "log\r\n");

    ::close(peer);  // the peer leaves
    std::uint8_t buf[32];
    std::size_t n = 0;
    std::int64_t host_ns = 0;
    EXPECT_EQ(client->read(buf, n, host_ns, 2s), ReadStatus::Closed);
    EXPECT_EQ(client->counters().closes, 1u);

    // The next reads reconnect after the 100 ms backoff (the listener's backlog completes the
    // handshake before accept); bounded loop, no sleeps.
    for (int i = 0; i < 50 && client->counters().reopens == 0; ++i)
        client->read(buf, n, host_ns, 200ms);
    EXPECT_EQ(client->counters().reopens, 1u);
    peer = server.accept_within(5000);
    ASSERT_GE(peer, 0);
    ASSERT_EQ(::send(peer, "again", 5, 0), 5);
    EXPECT_EQ(read_exactly(*client, 5), "again");
    ::close(peer);
}

TEST(TcpStream, refused_connection_is_an_io_error_naming_the_endpoint) {
    Listener refusing(false);
    const std::string uri = at("tcp://127.0.0.1:", refusing.port);
    try {
        open_byte_stream(uri);
        FAIL() << "no IoError";
    } catch (const IoError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(at("tcp '127.0.0.1:", refusing.port) + "'"), std::string::npos) << msg;
        EXPECT_NE(msg.find("refused"), std::string::npos) << msg;
    }
}

TEST(UdpStream, delivers_each_datagram_whole_with_a_monotonic_receive_time) {
    auto rx = open_byte_stream("udp://127.0.0.1:0");
    const std::uint16_t port = rx->local_port();
    ASSERT_NE(port, 0);
    auto tx = open_byte_stream(at("udp://127.0.0.1:", port) + "?send");
    EXPECT_EQ(tx->name(), at("udp://127.0.0.1:", port) + "?send");

    std::uint8_t buf[128];
    std::size_t n = 0;
    std::int64_t host_ns = 0;
    EXPECT_EQ(rx->read(buf, n, host_ns, 20ms), ReadStatus::Timeout);

    const std::int64_t before = hostclock::monotonic_ns();
    const std::string d1(72, 'N');  // an NCOM-sized datagram
    ASSERT_TRUE(tx->write(bytes_of(d1)));
    ASSERT_TRUE(tx->write(bytes_of("ab")));
    ASSERT_TRUE(tx->write(bytes_of("")));  // an empty datagram is still one datagram
    ASSERT_TRUE(tx->write(bytes_of(std::string(200, 'x'))));  // longer than the buffer
    ASSERT_TRUE(tx->write(bytes_of("end")));

    ASSERT_EQ(rx->read(buf, n, host_ns, 2s), ReadStatus::Data);
    EXPECT_EQ(n, 72u);
    EXPECT_EQ(std::string(reinterpret_cast<char*>(buf), n), d1);
    // Kernel receive time moved onto CLOCK_MONOTONIC: after the send started, not in the future.
    EXPECT_GE(host_ns, before - 1'000'000);  // 1 ms slack for the realtime/monotonic offset
    EXPECT_LE(host_ns, hostclock::monotonic_ns());
    ASSERT_EQ(rx->read(buf, n, host_ns, 2s), ReadStatus::Data);
    EXPECT_EQ(std::string(reinterpret_cast<char*>(buf), n), "ab");
    ASSERT_EQ(rx->read(buf, n, host_ns, 2s), ReadStatus::Data);
    EXPECT_EQ(n, 0u);
    ASSERT_EQ(rx->read(buf, n, host_ns, 2s), ReadStatus::Data);
    EXPECT_EQ(n, sizeof buf);  // truncated to the buffer; the rest of that datagram is dropped
    ASSERT_EQ(rx->read(buf, n, host_ns, 2s), ReadStatus::Data);
    EXPECT_EQ(std::string(reinterpret_cast<char*>(buf), n), "end");

    EXPECT_EQ(tx->counters().bytes_out, 72u + 2u + 200u + 3u);
    EXPECT_EQ(rx->counters().reads, 5u);
    EXPECT_EQ(rx->counters().bytes_in, 72u + 2u + 128u + 3u);
}

TEST(UdpStream, receiver_on_any_address_with_ephemeral_port) {
    auto rx = open_byte_stream("udp://:0");
    ASSERT_NE(rx->local_port(), 0);
    auto tx = open_byte_stream(at("udp://127.0.0.1:", rx->local_port()) + "?send");
    ASSERT_TRUE(tx->write(bytes_of("ncom")));
    EXPECT_EQ(read_exactly(*rx, 4), "ncom");
}

TEST(UdpStream, bind_conflict_is_an_io_error) {
    auto rx = open_byte_stream("udp://127.0.0.1:0");
    const std::string uri = at("udp://127.0.0.1:", rx->local_port());
    try {
        open_byte_stream(uri);
        FAIL() << "no IoError";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find("bind"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace mirage::bytestream
