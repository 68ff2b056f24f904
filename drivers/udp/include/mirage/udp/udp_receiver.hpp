// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mirage/core/time.hpp"

namespace mirage::udp {

struct ReceiverConfig {
    std::string bind_address = "127.0.0.1";  // "0.0.0.0" to also get broadcasts
    std::uint16_t port = 0;                  // 0: ephemeral, see UdpReceiver::port()
    std::string multicast_group;             // join this group (binds 0.0.0.0) when not empty
    std::string multicast_interface = "127.0.0.1";
    int receive_buffer_bytes = 4 << 20;  // SO_RCVBUF (capped by net.core.rmem_max)
};

struct ReceivedDatagram {
    std::vector<std::uint8_t> payload;
    std::int64_t kernel_time_ns = 0;  // SO_TIMESTAMPNS: CLOCK_REALTIME ns at reception; 0 if none
    std::array<std::uint8_t, 4> src_ip{};
    std::uint16_t src_port = 0;
    bool truncated = false;  // longer than 65535 bytes (MSG_TRUNC)
};

// A UDP receiver for tests and benchmarks (POSIX sockets): kernel receive timestamps via recvmsg
// and receives with a deadline via poll.
class UdpReceiver {
  public:
    // Throws ConfigError (bad address) or IoError (socket, bind, join) naming address and port.
    explicit UdpReceiver(const ReceiverConfig& config = {});
    ~UdpReceiver();
    UdpReceiver(const UdpReceiver&) = delete;
    UdpReceiver& operator=(const UdpReceiver&) = delete;

    std::uint16_t port() const { return port_; }
    // Waits up to `timeout` for one datagram; false on timeout or error (never throws).
    bool receive(ReceivedDatagram& out, core::Nanos timeout);
    // Reads everything already queued (no wait); returns how many datagrams were dropped.
    std::size_t drain();

  private:
    int fd_ = -1;
    std::uint16_t port_ = 0;
    std::vector<std::uint8_t> buffer_ = std::vector<std::uint8_t>(65536);
};

}  // namespace mirage::udp
