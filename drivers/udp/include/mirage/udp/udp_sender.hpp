// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "mirage/wire/packet.hpp"

namespace mirage::udp {

// A port per wire::Stream; 0 means "this stream is not sent" (destination) or "ephemeral"
// (source).
struct StreamPorts {
    std::uint16_t data = 2368;
    std::uint16_t position = 8308;
    std::uint16_t imu = 7503;
    std::uint16_t port(wire::Stream s) const {
        return s == wire::Stream::Data ? data : s == wire::Stream::Position ? position : imu;
    }
};

struct SenderConfig {
    std::string host = "127.0.0.1";     // IPv4 address or name (resolved once, IPv4)
    StreamPorts ports;                  // destination port per stream
    StreamPorts source_ports{0, 0, 0};  // bind these local ports (a Velodyne sends 2368->2368)
    std::string source_address;         // local address to bind; empty: any
    int multicast_ttl = 1;              // IP_MULTICAST_TTL
    bool multicast_loop = true;         // IP_MULTICAST_LOOP: local listeners get a copy
    std::string multicast_interface;    // outgoing interface: IPv4 address or name; empty: route
    int send_buffer_bytes = 0;          // SO_SNDBUF; 0: system default
};

enum class DestinationKind : std::uint8_t { Unicast, Broadcast, Multicast };

// Multicast: 224.0.0.0/4. Broadcast: 255.255.255.255, or the directed broadcast address of one of
// this host's IPv4 interfaces (address | ~netmask, e.g. 192.168.1.255 on a /24, 127.255.255.255).
DestinationKind classify_destination(const std::array<std::uint8_t, 4>& ip);

struct SendCounters {
    std::uint64_t sent = 0;  // datagrams the kernel accepted
    std::uint64_t failed =
        0;  // refused (ECONNREFUSED after ICMP port unreachable), ENOBUFS, EAGAIN...
    std::uint64_t skipped = 0;  // streams configured with destination port 0
    std::uint64_t bytes = 0;    // payload bytes sent
};

// Sends each stream's packets from its own UDP socket (Boost.Asio), connected to host:port so the
// kernel reports ICMP errors back to it. Sends are synchronous and non-blocking: a full socket
// buffer is a failed send, never a stall. Failures are counted and printed to stderr at most once
// per second with their count; send() never throws and the stream never stops.
class UdpSender {
  public:
    // Throws ConfigError (bad host, multicast interface) or IoError (socket, bind, option),
    // naming the host and port.
    explicit UdpSender(const SenderConfig& config);
    ~UdpSender();
    UdpSender(const UdpSender&) = delete;
    UdpSender& operator=(const UdpSender&) = delete;

    bool send(const wire::PacketView& packet) { return send(packet.stream, packet.bytes); }
    bool send(wire::Stream stream, std::span<const std::uint8_t> bytes);

    const SendCounters& counters(wire::Stream stream) const;
    SendCounters total() const;
    DestinationKind destination_kind() const { return kind_; }
    const std::array<std::uint8_t, 4>& destination() const { return dest_ip_; }
    // Local port a stream's socket is bound to (0 if the stream is not sent).
    std::uint16_t local_port(wire::Stream stream) const;

  private:
    struct Impl;
    Impl* impl_;
    DestinationKind kind_ = DestinationKind::Unicast;
    std::array<std::uint8_t, 4> dest_ip_{};
};

}  // namespace mirage::udp
