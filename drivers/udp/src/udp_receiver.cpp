// SPDX-License-Identifier: Apache-2.0
#include "mirage/udp/udp_receiver.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <ctime>

#include "mirage/core/error.hpp"
#include "mirage/udp/pacer.hpp"

namespace mirage::udp {
namespace {

constexpr std::size_t kMaxDatagram = 65535;

in_addr parse_v4(const std::string& text, const char* what) {
    in_addr a{};
    if (inet_pton(AF_INET, text.c_str(), &a) != 1)
        throw ConfigError(fmt::format("udp receiver: {} '{}': not an IPv4 address", what, text));
    return a;
}

}  // namespace

UdpReceiver::UdpReceiver(const ReceiverConfig& config) {
    const bool multicast = !config.multicast_group.empty();
    const std::string bind_text = multicast ? "0.0.0.0" : config.bind_address;
    const in_addr bind_addr = parse_v4(bind_text, "bind address");
    const std::string where = fmt::format("udp receiver {}:{}", bind_text, config.port);
    auto fail = [&](const char* what) {
        const int err = errno;
        if (fd_ >= 0) ::close(fd_);
        throw IoError(fmt::format("{}: {}: {}", where, what, std::strerror(err)));
    };
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) fail("socket");
    const int one = 1;
    if (::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one) != 0)
        fail("SO_TIMESTAMPNS");
    if (multicast && ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one) != 0)
        fail("SO_REUSEADDR");
    if (config.receive_buffer_bytes > 0)
        ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &config.receive_buffer_bytes,
                     sizeof config.receive_buffer_bytes);  // best effort: capped by rmem_max
    sockaddr_in sa{};
    sa.sin_family = AF_INET;
    sa.sin_port = htons(config.port);
    sa.sin_addr = bind_addr;
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&sa), sizeof sa) != 0) fail("bind");
    socklen_t len = sizeof sa;
    if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&sa), &len) != 0) fail("getsockname");
    port_ = ntohs(sa.sin_port);
    if (multicast) {
        ip_mreq mreq{};
        mreq.imr_multiaddr = parse_v4(config.multicast_group, "multicast group");
        mreq.imr_interface = parse_v4(config.multicast_interface, "multicast interface");
        if (::setsockopt(fd_, IPPROTO_IP, IP_ADD_MEMBERSHIP, &mreq, sizeof mreq) != 0)
            fail("IP_ADD_MEMBERSHIP");
    }
}

UdpReceiver::~UdpReceiver() {
    if (fd_ >= 0) ::close(fd_);
}

bool UdpReceiver::receive(ReceivedDatagram& out, core::Nanos timeout) {
    pollfd p{fd_, POLLIN, 0};
    const auto ms = static_cast<int>((timeout.count() + 999'999) / 1'000'000);
    int rc;
    do {
        rc = ::poll(&p, 1, ms);
    } while (rc < 0 && errno == EINTR);
    if (rc <= 0) return false;

    // One byte more than the largest datagram, so MSG_TRUNC only flags the impossible.
    iovec iov{buffer_.data(), kMaxDatagram};
    sockaddr_in from{};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec))];
    msghdr msg{};
    msg.msg_name = &from;
    msg.msg_namelen = sizeof from;
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t n = ::recvmsg(fd_, &msg, MSG_DONTWAIT);
    if (n < 0) return false;
    out.payload.assign(buffer_.begin(), buffer_.begin() + n);
    out.truncated = (msg.msg_flags & MSG_TRUNC) != 0;
    std::memcpy(out.src_ip.data(), &from.sin_addr, 4);
    out.src_port = ntohs(from.sin_port);
    out.kernel_time_ns = 0;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
            timespec ts{};
            std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
            out.kernel_time_ns = static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
        }
    }
    return true;
}

std::size_t UdpReceiver::drain() {
    std::size_t n = 0;
    char buf[64];
    while (::recv(fd_, buf, sizeof buf, MSG_DONTWAIT) >= 0) ++n;
    return n;
}

}  // namespace mirage::udp
