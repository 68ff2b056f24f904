// SPDX-License-Identifier: Apache-2.0
// TCP client and UDP sockets as byte streams.
#include <fcntl.h>
#include <fmt/format.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <ctime>

#include "fd_stream.hpp"
#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "streams.hpp"

namespace mirage::bytestream::detail {
namespace {

constexpr int kConnectTimeoutMs = 2000;

std::string endpoint(const std::string& host, std::uint16_t port) {
    return host.find(':') != std::string::npos ? fmt::format("[{}]:{}", host, port)
                                               : fmt::format("{}:{}", host, port);
}

struct AddrList {
    addrinfo* head = nullptr;
    ~AddrList() {
        if (head) ::freeaddrinfo(head);
    }
};

// getaddrinfo; the error text (empty on success).
std::string resolve(const std::string& host, std::uint16_t port, int socktype, bool passive,
                    AddrList& out) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = socktype;
    hints.ai_flags = AI_NUMERICSERV | (passive ? AI_PASSIVE : 0);
    if (passive && host.empty()) hints.ai_family = AF_INET;  // "udp://:3000": 0.0.0.0
    const std::string service = std::to_string(port);
    const int rc =
        ::getaddrinfo(host.empty() ? nullptr : host.c_str(), service.c_str(), &hints, &out.head);
    return rc == 0 ? std::string() : std::string(::gai_strerror(rc));
}

std::uint16_t bound_port(int fd) {
    sockaddr_storage ss{};
    socklen_t len = sizeof ss;
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&ss), &len) != 0) return 0;
    if (ss.ss_family == AF_INET) return ntohs(reinterpret_cast<sockaddr_in*>(&ss)->sin_port);
    if (ss.ss_family == AF_INET6) return ntohs(reinterpret_cast<sockaddr_in6*>(&ss)->sin6_port);
    return 0;
}

// Non-blocking connect with a timeout; -1 and `error` on failure.
int connect_tcp(const std::string& host, std::uint16_t port, int timeout_ms, std::string& error) {
    AddrList addrs;
    error = resolve(host, port, SOCK_STREAM, false, addrs);
    if (!error.empty()) return -1;
    error = "no address";
    for (addrinfo* a = addrs.head; a != nullptr; a = a->ai_next) {
        const int fd =
            ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
        if (fd < 0) {
            error = std::string("socket: ") + std::strerror(errno);
            continue;
        }
        int err = 0;
        if (::connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
            err = errno;
            if (err == EINPROGRESS) {
                pollfd p{fd, POLLOUT, 0};
                int rc;
                do {
                    rc = ::poll(&p, 1, timeout_ms);
                } while (rc < 0 && errno == EINTR);
                socklen_t len = sizeof err;
                if (rc == 0)
                    err = ETIMEDOUT;
                else if (::getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len) != 0)
                    err = errno;
            }
        }
        if (err == 0) {
            const int one = 1;
            ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            return fd;
        }
        error = std::string("connect: ") + std::strerror(err);
        ::close(fd);
    }
    return -1;
}

class TcpClient final : public FdStream {
  public:
    TcpClient(std::string host, std::uint16_t port)
        : FdStream("tcp://" + endpoint(host, port), Kind::Stream, true),
          host_(std::move(host)),
          port_(port) {
        std::string error;
        const int fd = connect_tcp(host_, port_, kConnectTimeoutMs, error);
        if (fd < 0) throw IoError(fmt::format("tcp '{}': {}", endpoint(host_, port_), error));
        adopt(fd);
    }
    std::uint16_t local_port() const override { return bound_port(fd()); }

  protected:
    int reopen_fd() override {
        std::string error;
        // Short: a reopen runs inside read(), which should not overrun its deadline by much.
        return connect_tcp(host_, port_, 200, error);
    }

  private:
    std::string host_;
    std::uint16_t port_;
};

class UdpSocket final : public FdStream {
  public:
    UdpSocket(const std::string& host, std::uint16_t port, bool sender)
        : FdStream(fmt::format("udp://{}{}", endpoint(host, port), sender ? "?send" : ""),
                   Kind::Datagram, false) {
        AddrList addrs;
        const std::string where = endpoint(host, port);
        std::string error = resolve(host, port, SOCK_DGRAM, !sender, addrs);
        if (!error.empty()) throw IoError(fmt::format("udp '{}': {}", where, error));
        for (addrinfo* a = addrs.head; a != nullptr; a = a->ai_next) {
            const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC,
                                    a->ai_protocol);
            if (fd < 0) {
                error = std::string("socket: ") + std::strerror(errno);
                continue;
            }
            const int one = 1;
            bool ok;
            if (sender) {
                ok = ::connect(fd, a->ai_addr, a->ai_addrlen) == 0;
                if (!ok) error = std::string("connect: ") + std::strerror(errno);
            } else {
                ::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one);
                const int rcvbuf = 4 << 20;  // best effort: capped by net.core.rmem_max
                ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
                ok = ::bind(fd, a->ai_addr, a->ai_addrlen) == 0;
                if (!ok) error = std::string("bind: ") + std::strerror(errno);
            }
            if (ok) {
                adopt(fd);
                return;
            }
            ::close(fd);
        }
        throw IoError(fmt::format("udp '{}': {}", where, error));
    }
    std::uint16_t local_port() const override { return bound_port(fd()); }

  protected:
    // One datagram per read; the kernel receive time (SO_TIMESTAMPNS, CLOCK_REALTIME) is moved
    // onto CLOCK_MONOTONIC with the offset between the two clocks read now.
    long read_once(int fd, std::span<std::uint8_t> buffer, std::int64_t& host_ns) override {
        iovec iov{buffer.data(), buffer.size()};
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec))];
        msghdr msg{};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        msg.msg_control = control;
        msg.msg_controllen = sizeof control;
        const long n = static_cast<long>(::recvmsg(fd, &msg, MSG_DONTWAIT));
        const std::int64_t mono0 = hostclock::monotonic_ns();
        host_ns = mono0;
        if (n < 0) return n;
        for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
            if (c->cmsg_level != SOL_SOCKET || c->cmsg_type != SCM_TIMESTAMPNS) continue;
            timespec kt{}, rt{};
            std::memcpy(&kt, CMSG_DATA(c), sizeof kt);
            clock_gettime(CLOCK_REALTIME, &rt);
            const std::int64_t mono1 = hostclock::monotonic_ns();
            const std::int64_t rt_ns =
                static_cast<std::int64_t>(rt.tv_sec) * 1'000'000'000 + rt.tv_nsec;
            const std::int64_t offset = rt_ns - (mono0 + (mono1 - mono0) / 2);
            const std::int64_t k_ns =
                static_cast<std::int64_t>(kt.tv_sec) * 1'000'000'000 + kt.tv_nsec;
            host_ns = std::min(k_ns - offset, mono1);
        }
        return n;
    }
};

}  // namespace

std::unique_ptr<ByteStream> open_tcp_client(const std::string& host, std::uint16_t port) {
    return std::make_unique<TcpClient>(host, port);
}
std::unique_ptr<ByteStream> open_udp_receiver(const std::string& bind_host, std::uint16_t port) {
    return std::make_unique<UdpSocket>(bind_host, port, false);
}
std::unique_ptr<ByteStream> open_udp_sender(const std::string& host, std::uint16_t port) {
    return std::make_unique<UdpSocket>(host, port, true);
}

}  // namespace mirage::bytestream::detail
