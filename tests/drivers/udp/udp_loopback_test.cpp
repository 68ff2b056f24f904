// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cstring>
#include <iostream>
#include <optional>

#include "mirage/core/error.hpp"
#include "mirage/udp/pacing_probe.hpp"
#include "mirage/udp/udp_receiver.hpp"
#include "mirage/udp/udp_sender.hpp"

namespace {

using mirage::core::Nanos;
using mirage::udp::DestinationKind;
using mirage::udp::ReceivedDatagram;
using mirage::udp::ReceiverConfig;
using mirage::udp::SenderConfig;
using mirage::udp::StreamPorts;
using mirage::udp::UdpReceiver;
using mirage::udp::UdpSender;
using mirage::wire::Stream;
using Bytes = std::vector<std::uint8_t>;

constexpr Nanos kTimeout{2'000'000'000};  // generous: the machine is shared

Bytes numbered(std::uint32_t k, std::size_t size) {
    Bytes b(std::max<std::size_t>(size, 4));
    for (std::size_t i = 0; i < b.size(); ++i) b[i] = static_cast<std::uint8_t>(i * 7 + k);
    std::memcpy(b.data(), &k, 4);
    return b;
}

SenderConfig to(std::uint16_t data, std::uint16_t position = 0, std::uint16_t imu = 0) {
    SenderConfig c;
    c.host = "127.0.0.1";
    c.ports = StreamPorts{data, position, imu};
    return c;
}

TEST(UdpLoopback, delivers_1000_packets_in_order_with_equal_bytes) {
    UdpReceiver rx;
    ASSERT_NE(rx.port(), 0);
    UdpSender tx(to(rx.port()));
    EXPECT_EQ(tx.destination_kind(), DestinationKind::Unicast);
    ReceivedDatagram d;
    std::size_t bytes = 0;
    // Bursts of 50 stay well inside a default 208 KiB receive buffer.
    for (std::uint32_t burst = 0; burst < 20; ++burst) {
        for (std::uint32_t i = 0; i < 50; ++i) {
            const std::uint32_t k = burst * 50 + i;
            const auto p = numbered(k, 1 + (k * 37) % 1206);
            bytes += p.size();
            ASSERT_TRUE(tx.send(Stream::Data, p)) << k;
        }
        for (std::uint32_t i = 0; i < 50; ++i) {
            const std::uint32_t k = burst * 50 + i;
            ASSERT_TRUE(rx.receive(d, kTimeout)) << k;
            EXPECT_EQ(d.payload, numbered(k, 1 + (k * 37) % 1206)) << k;
            EXPECT_EQ(d.src_port, tx.local_port(Stream::Data));
            EXPECT_GT(d.kernel_time_ns, 0);
            EXPECT_FALSE(d.truncated);
        }
    }
    EXPECT_EQ(tx.counters(Stream::Data).sent, 1000u);
    EXPECT_EQ(tx.counters(Stream::Data).failed, 0u);
    EXPECT_EQ(tx.counters(Stream::Data).bytes, bytes);
}

TEST(UdpLoopback, sends_each_stream_to_its_own_port_from_the_bound_source_port) {
    UdpReceiver data, position, imu;
    std::uint16_t source = 0;
    {
        UdpReceiver probe;  // find a free port for the sender to bind
        source = probe.port();
    }
    SenderConfig c = to(data.port(), position.port(), imu.port());
    c.source_ports.data = source;
    c.source_address = "127.0.0.1";
    UdpSender tx(c);
    EXPECT_EQ(tx.local_port(Stream::Data), source);
    ASSERT_TRUE(tx.send(mirage::wire::PacketView{Stream::Data, {}, numbered(1, 1206)}));
    ASSERT_TRUE(tx.send(mirage::wire::PacketView{Stream::Position, {}, numbered(2, 512)}));
    ASSERT_TRUE(tx.send(mirage::wire::PacketView{Stream::Imu, {}, numbered(3, 48)}));
    ReceivedDatagram d;
    ASSERT_TRUE(data.receive(d, kTimeout));
    EXPECT_EQ(d.payload, numbered(1, 1206));
    EXPECT_EQ(d.src_port, source);
    ASSERT_TRUE(position.receive(d, kTimeout));
    EXPECT_EQ(d.payload, numbered(2, 512));
    ASSERT_TRUE(imu.receive(d, kTimeout));
    EXPECT_EQ(d.payload, numbered(3, 48));
    // Each receiver got exactly its stream: nothing else is queued.
    EXPECT_EQ(data.drain() + position.drain() + imu.drain(), 0u);
    EXPECT_EQ(tx.total().sent, 3u);
}

TEST(UdpLoopback, skips_a_stream_without_a_port) {
    UdpReceiver rx;
    UdpSender tx(to(rx.port()));
    EXPECT_FALSE(tx.send(Stream::Imu, numbered(0, 48)));
    EXPECT_EQ(tx.counters(Stream::Imu).skipped, 1u);
    EXPECT_EQ(tx.local_port(Stream::Imu), 0);
}

TEST(UdpLoopback, counts_refused_sends_without_a_listener_and_keeps_going) {
    std::uint16_t closed = 0;
    {
        UdpReceiver gone;
        closed = gone.port();
    }
    UdpSender tx(to(closed));
    for (std::uint32_t k = 0; k < 200; ++k) tx.send(Stream::Data, numbered(k, 100));
    const auto& c = tx.counters(Stream::Data);
    std::cout << "no listener: " << c.sent << " sent, " << c.failed << " refused\n";
    EXPECT_EQ(c.sent + c.failed, 200u);
    EXPECT_GT(c.failed, 0u);  // ICMP port unreachable -> ECONNREFUSED on the connected socket
    EXPECT_GT(c.sent, 0u);    // and sending went on
}

TEST(UdpLoopback, broadcasts_to_the_loopback_subnet_broadcast_address) {
    ReceiverConfig rc;
    rc.bind_address = "0.0.0.0";  // a socket bound to 127.0.0.1 does not get broadcasts
    UdpReceiver rx(rc);
    SenderConfig c = to(rx.port());
    c.host = "127.255.255.255";  // directed broadcast of lo's 127.0.0.1/8
    UdpSender tx(c);
    ASSERT_EQ(tx.destination_kind(), DestinationKind::Broadcast);
    ASSERT_TRUE(tx.send(Stream::Data, numbered(5, 1206)));  // EACCES without SO_BROADCAST
    ReceivedDatagram d;
    ASSERT_TRUE(rx.receive(d, kTimeout));
    EXPECT_EQ(d.payload, numbered(5, 1206));
}

TEST(UdpLoopback, classifies_destinations) {
    using mirage::udp::classify_destination;
    EXPECT_EQ(classify_destination({255, 255, 255, 255}), DestinationKind::Broadcast);
    EXPECT_EQ(classify_destination({127, 255, 255, 255}), DestinationKind::Broadcast);
    EXPECT_EQ(classify_destination({239, 1, 2, 3}), DestinationKind::Multicast);
    EXPECT_EQ(classify_destination({224, 0, 0, 1}), DestinationKind::Multicast);
    EXPECT_EQ(classify_destination({127, 0, 0, 1}), DestinationKind::Unicast);
    EXPECT_EQ(classify_destination({10, 11, 12, 13}), DestinationKind::Unicast);
}

TEST(UdpLoopback, multicasts_to_a_group_joined_on_loopback) {
    ReceiverConfig rc;
    rc.multicast_group = "239.255.77.1";
    rc.multicast_interface = "127.0.0.1";
    std::optional<UdpReceiver> rx;
    try {
        rx.emplace(rc);
    } catch (const mirage::IoError& e) {
        GTEST_SKIP() << "cannot join a multicast group on lo in this environment: " << e.what();
    }
    SenderConfig c = to(rx->port());
    c.host = "239.255.77.1";
    c.multicast_interface = "127.0.0.1";  // IP_MULTICAST_IF; IP_MULTICAST_LOOP on by default
    UdpSender tx(c);
    ASSERT_EQ(tx.destination_kind(), DestinationKind::Multicast);
    for (std::uint32_t k = 0; k < 10; ++k) tx.send(Stream::Data, numbered(k, 600));
    if (tx.counters(Stream::Data).sent == 0)
        GTEST_SKIP() << "multicast sends over lo refused in this environment";
    ReceivedDatagram d;
    for (std::uint32_t k = 0; k < 10; ++k) {
        ASSERT_TRUE(rx->receive(d, kTimeout)) << k;
        EXPECT_EQ(d.payload, numbered(k, 600));
    }
}

TEST(UdpLoopback, setup_errors_name_the_host_and_port) {
    try {
        SenderConfig c = to(2368);
        c.host = "no-such-host.invalid";
        UdpSender tx(c);
        FAIL() << "no exception";
    } catch (const mirage::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("no-such-host.invalid"), std::string::npos);
    }
    UdpReceiver busy;
    SenderConfig c = to(2368);
    c.source_address = "127.0.0.1";
    c.source_ports.data = busy.port();
    try {
        UdpSender tx(c);
        FAIL() << "no exception";
    } catch (const mirage::IoError& e) {
        EXPECT_NE(std::string(e.what()).find(std::to_string(busy.port())), std::string::npos)
            << e.what();
    }
    ReceiverConfig rc;
    rc.bind_address = "127.0.0.1";
    rc.port = busy.port();
    EXPECT_THROW(UdpReceiver again(rc), mirage::IoError);
}

// 2000 packets at 10 kHz: the kernel receive times follow the schedule without drift.
TEST(UdpLoopback, pacer_holds_a_10_khz_schedule_without_drift) {
    mirage::udp::PacingProbeConfig config;
    config.rate_hz = 10'000;
    config.packets = 2'000;
    const auto r = mirage::udp::run_pacing_probe(config);
    std::cout << mirage::udp::format_report(r) << "\n";
    ASSERT_EQ(r.received, 2000u);
    EXPECT_EQ(r.schedule_span, Nanos{199'900'000});
    // Drift = change of the least lateness from the first to the last 200 packets. The raw
    // first-to-last span is printed, not asserted: one packet delayed by a busy shared machine
    // would move it by milliseconds without any drift.
    EXPECT_LT(std::abs(r.drift.count()), 1'000'000);
    EXPECT_GE(r.wire.best(), Nanos{-50'000});  // nothing leaves noticeably before its deadline
}

}  // namespace
