// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <netinet/in.h>
#include <sys/socket.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace mirage::replay {

// One datagram to send: payload and destination port (the host is the sender's).
struct Outgoing {
    std::span<const std::uint8_t> payload;
    std::uint16_t port = 0;
};

// One unconnected IPv4 UDP socket sending to host:<any port> with sendmmsg(2), up to kMaxBatch
// messages per system call: the top-speed path of `mirage replay --speed 0`. Runs of adjacent
// datagrams with the same port and size (a lidar's data packets) go as one UDP GSO message
// (UDP_SEGMENT, Linux ≥ 4.18): the kernel walks its stack once per run and splits it into the
// same datagrams, in order. Where GSO is refused (no checksum offload on the route, a size above
// the path MTU, an older kernel) the run is re-sent as single datagrams and GSO is not tried
// again for that size. Blocking socket: a full send buffer waits instead of dropping. Never
// throws after construction.
class BatchSender {
  public:
    static constexpr std::size_t kMaxBatch = 128;
    static constexpr std::size_t kMaxSegments = 64;  // UDP_MAX_SEGMENTS of Linux < 6.9
    // Throws ConfigError naming the host when it does not resolve (IPv4), IoError when the
    // socket cannot be made. send_buffer_bytes 0: system default.
    explicit BatchSender(const std::string& host, int send_buffer_bytes = 4 << 20, bool gso = true);
    ~BatchSender();
    BatchSender(const BatchSender&) = delete;
    BatchSender& operator=(const BatchSender&) = delete;

    // Sends all of `batch` (any size; split into kMaxBatch calls). Returns how many the kernel
    // accepted; the others are counted in failed() with the last errno in last_error().
    std::size_t send(std::span<const Outgoing> batch);

    std::uint64_t sent() const { return sent_; }
    std::uint64_t failed() const { return failed_; }
    std::uint64_t syscalls() const { return syscalls_; }
    std::uint64_t gso_messages() const { return gso_messages_; }  // runs sent as one GSO message
    int last_error() const { return last_error_; }
    const std::array<std::uint8_t, 4>& address() const { return ip_; }

  private:
    // Sends the start of `batch` as up to kMaxBatch messages (each one datagram or one GSO run);
    // returns the datagrams accepted and sets `consumed` to how many of `batch` were dealt with
    // (sent or failed). A run refused GSO stops it there, so the next call re-sends it singly.
    std::size_t send_some(std::span<const Outgoing> batch, std::size_t& consumed);
    std::size_t run_length(std::span<const Outgoing> batch, std::size_t i) const;

    struct Buffers {
        std::vector<mmsghdr> msgs = std::vector<mmsghdr>(kMaxBatch);
        std::vector<iovec> iov = std::vector<iovec>(kMaxBatch * kMaxSegments);
        std::vector<sockaddr_in> addr = std::vector<sockaddr_in>(kMaxBatch);
        struct alignas(cmsghdr) Control {  // one UDP_SEGMENT control message
            unsigned char bytes[CMSG_SPACE(sizeof(std::uint16_t))];
        };
        std::vector<Control> control = std::vector<Control>(kMaxBatch);
        std::vector<std::size_t> first = std::vector<std::size_t>(kMaxBatch);
        std::vector<std::size_t> count = std::vector<std::size_t>(kMaxBatch);
    };
    Buffers buf_;
    int fd_ = -1;
    std::array<std::uint8_t, 4> ip_{};
    bool gso_ = true;
    std::size_t gso_refused_size_ =
        std::numeric_limits<std::size_t>::max();  // smallest payload size GSO was refused for
    std::uint64_t sent_ = 0, failed_ = 0, syscalls_ = 0, gso_messages_ = 0;
    int last_error_ = 0;
};

}  // namespace mirage::replay
