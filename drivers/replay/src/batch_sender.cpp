// SPDX-License-Identifier: Apache-2.0
#include "mirage/replay/batch_sender.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/udp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

#include "mirage/core/error.hpp"

#ifndef UDP_SEGMENT
#define UDP_SEGMENT 103  // linux/udp.h; glibc's netinet/udp.h has it from 2.29 on
#endif

namespace mirage::replay {
namespace {
constexpr std::size_t kMaxGsoBytes = 65507;  // largest UDP payload of one IPv4 datagram
}  // namespace

BatchSender::BatchSender(const std::string& host, int send_buffer_bytes, bool gso) : gso_(gso) {
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

// Datagrams from i on that can share one GSO message with batch[i].
std::size_t BatchSender::run_length(std::span<const Outgoing> batch, std::size_t i) const {
    const std::size_t size = batch[i].payload.size();
    if (!gso_ || size == 0 || size >= gso_refused_size_) return 1;
    std::size_t n = 1, total = size;
    while (i + n < batch.size() && n < kMaxSegments && batch[i + n].port == batch[i].port &&
           batch[i + n].payload.size() == size && total + size <= kMaxGsoBytes) {
        total += size;
        ++n;
    }
    return n;
}

std::size_t BatchSender::send_some(std::span<const Outgoing> batch, std::size_t& consumed) {
    // Member buffers, allocated and touched in the constructor: on the stack these 150 kB
    // page-faulted in the first call and made the first datagram hundreds of µs late.
    auto& msgs = buf_.msgs;
    auto& iov = buf_.iov;
    auto& addr = buf_.addr;
    auto& control = buf_.control;
    auto& first = buf_.first;
    auto& count = buf_.count;
    std::fill(msgs.begin(), msgs.end(), mmsghdr{});
    std::size_t m = 0, i = 0, v = 0;
    while (m < kMaxBatch && i < batch.size()) {
        const std::size_t n = run_length(batch, i);
        for (std::size_t k = 0; k < n; ++k) {
            const auto& o = batch[i + k];
            iov[v + k].iov_base = const_cast<std::uint8_t*>(o.payload.data());
            iov[v + k].iov_len = o.payload.size();
        }
        addr[m].sin_family = AF_INET;
        addr[m].sin_port = htons(batch[i].port);
        std::memcpy(&addr[m].sin_addr, ip_.data(), 4);
        msghdr& h = msgs[m].msg_hdr;
        h.msg_name = &addr[m];
        h.msg_namelen = sizeof(sockaddr_in);
        h.msg_iov = &iov[v];
        h.msg_iovlen = n;
        if (n > 1) {
            h.msg_control = control[m].bytes;
            h.msg_controllen = sizeof control[m].bytes;
            cmsghdr* c = CMSG_FIRSTHDR(&h);
            c->cmsg_level = SOL_UDP;
            c->cmsg_type = UDP_SEGMENT;
            c->cmsg_len = CMSG_LEN(sizeof(std::uint16_t));
            const auto seg = static_cast<std::uint16_t>(batch[i].payload.size());
            std::memcpy(CMSG_DATA(c), &seg, sizeof seg);
        }
        first[m] = i;
        count[m] = n;
        i += n;
        v += n;
        ++m;
    }
    std::size_t accepted = 0, done = 0;
    while (done < m) {
        ++syscalls_;
        const int rc = ::sendmmsg(fd_, msgs.data() + done, static_cast<unsigned>(m - done), 0);
        if (rc < 0) {
            if (errno == EINTR) continue;
            if (count[done] > 1) {
                // GSO refused for this run: its datagrams go again singly (next call).
                gso_refused_size_ = std::min(gso_refused_size_, batch[first[done]].payload.size());
                if (errno == EIO || errno == ENOPROTOOPT || errno == EOPNOTSUPP) gso_ = false;
                consumed = first[done];
                return accepted;
            }
            // The first message of the rest failed: count it and go on with the others.
            last_error_ = errno;
            ++failed_;
            ++done;
            continue;
        }
        for (int k = 0; k < rc; ++k) {
            const std::size_t c = count[done + static_cast<std::size_t>(k)];
            accepted += c;
            if (c > 1) ++gso_messages_;
        }
        done += static_cast<std::size_t>(rc);
    }
    consumed = i;
    return accepted;
}

std::size_t BatchSender::send(std::span<const Outgoing> batch) {
    std::size_t accepted = 0, i = 0;
    while (i < batch.size()) {
        std::size_t consumed = 0;
        accepted += send_some(batch.subspan(i), consumed);
        i += consumed;
    }
    sent_ += accepted;
    return accepted;
}

}  // namespace mirage::replay
