// SPDX-License-Identifier: Apache-2.0
#include "mirage/replay/batch_sender.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "mirage/core/error.hpp"

namespace mirage::replay {

BatchSender::BatchSender(const std::string& host, int send_buffer_bytes) {
    addrinfo hints{};
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_DGRAM;
    addrinfo* res = nullptr;
    const int rc = ::getaddrinfo(host.c_str(), nullptr, &hints, &res);
    if (rc != 0 || res == nullptr)
        throw ConfigError(
            fmt::format("replay --to '{}': cannot resolve (IPv4): {}", host, gai_strerror(rc)));
    const auto* sin = reinterpret_cast<const sockaddr_in*>(res->ai_addr);
    std::memcpy(ip_.data(), &sin->sin_addr, 4);
    ::freeaddrinfo(res);

    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0)
        throw IoError(fmt::format("replay to '{}': socket: {}", host, std::strerror(errno)));
    const int one = 1;
    // Broadcast destinations (192.168.1.255) need SO_BROADCAST; harmless otherwise.
    ::setsockopt(fd_, SOL_SOCKET, SO_BROADCAST, &one, sizeof one);
    if (send_buffer_bytes > 0)
        ::setsockopt(fd_, SOL_SOCKET, SO_SNDBUF, &send_buffer_bytes, sizeof send_buffer_bytes);
}

BatchSender::~BatchSender() {
    if (fd_ >= 0) ::close(fd_);
}

std::size_t BatchSender::send(std::span<const Outgoing> batch) {
    std::array<mmsghdr, kMaxBatch> msgs{};
    std::array<iovec, kMaxBatch> iov{};
    std::array<sockaddr_in, kMaxBatch> addr{};
    std::size_t accepted = 0;
    std::size_t i = 0;
    while (i < batch.size()) {
        const std::size_t n = std::min(kMaxBatch, batch.size() - i);
        for (std::size_t k = 0; k < n; ++k) {
            const auto& o = batch[i + k];
            addr[k].sin_family = AF_INET;
            addr[k].sin_port = htons(o.port);
            std::memcpy(&addr[k].sin_addr, ip_.data(), 4);
            iov[k].iov_base = const_cast<std::uint8_t*>(o.payload.data());
            iov[k].iov_len = o.payload.size();
            msgs[k] = mmsghdr{};
            msgs[k].msg_hdr.msg_name = &addr[k];
            msgs[k].msg_hdr.msg_namelen = sizeof(sockaddr_in);
            msgs[k].msg_hdr.msg_iov = &iov[k];
            msgs[k].msg_hdr.msg_iovlen = 1;
        }
        std::size_t done = 0;
        while (done < n) {
            ++syscalls_;
            const int rc = ::sendmmsg(fd_, msgs.data() + done, static_cast<unsigned>(n - done), 0);
            if (rc < 0) {
                if (errno == EINTR) continue;
                // The first message of the rest failed: count it and go on with the others.
                last_error_ = errno;
                ++failed_;
                ++done;
                continue;
            }
            done += static_cast<std::size_t>(rc);
            accepted += static_cast<std::size_t>(rc);
            sent_ += static_cast<std::uint64_t>(rc);
        }
        i += n;
    }
    return accepted;
}

}  // namespace mirage::replay
