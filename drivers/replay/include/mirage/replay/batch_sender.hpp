// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
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
// datagrams per system call: the top-speed path of `mirage replay --speed 0`. Blocking socket:
// a full send buffer waits instead of dropping. Never throws after construction.
class BatchSender {
  public:
    static constexpr std::size_t kMaxBatch = 128;
    // Throws ConfigError naming the host when it does not resolve (IPv4), IoError when the
    // socket cannot be made. send_buffer_bytes 0: system default.
    explicit BatchSender(const std::string& host, int send_buffer_bytes = 4 << 20);
    ~BatchSender();
    BatchSender(const BatchSender&) = delete;
    BatchSender& operator=(const BatchSender&) = delete;

    // Sends all of `batch` (any size; split into kMaxBatch calls). Returns how many the kernel
    // accepted; the others are counted in failed() with the last errno in last_error().
    std::size_t send(std::span<const Outgoing> batch);

    std::uint64_t sent() const { return sent_; }
    std::uint64_t failed() const { return failed_; }
    std::uint64_t syscalls() const { return syscalls_; }
    int last_error() const { return last_error_; }
    const std::array<std::uint8_t, 4>& address() const { return ip_; }

  private:
    int fd_ = -1;
    std::array<std::uint8_t, 4> ip_{};
    std::uint64_t sent_ = 0, failed_ = 0, syscalls_ = 0;
    int last_error_ = 0;
};

}  // namespace mirage::replay
