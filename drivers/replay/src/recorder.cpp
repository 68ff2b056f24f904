// SPDX-License-Identifier: Apache-2.0
#include "mirage/replay/recorder.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/pcap/writer.hpp"
#include "mirage/replay/time_order.hpp"
#include "mirage/udp/pacer.hpp"
#include "mirage/udp/udp_receiver.hpp"

namespace mirage::replay {
namespace {

constexpr std::size_t kBatch = 32;
// Records wait this long for a datagram stamped earlier on another socket (TimeOrder).
constexpr std::int64_t kOrderHoldNs = 50'000'000;
constexpr std::size_t kMaxDatagram = 65535;

std::array<std::uint8_t, 4> ip_bytes(const in_addr& a) {
    std::array<std::uint8_t, 4> b{};
    std::memcpy(b.data(), &a, 4);
    return b;
}

}  // namespace

Recorder::Recorder(const RecordConfig& config) : config_(config) {
    if (config.ports.empty()) throw ConfigError("record --listen: no ports");
    in_addr bind_ip{};
    if (::inet_pton(AF_INET, config.bind_host.c_str(), &bind_ip) != 1)
        throw ConfigError(
            fmt::format("record --bind-host '{}': expected an IPv4 address", config.bind_host));
    auto fail = [&](std::uint16_t port, const char* what) {
        const int err = errno;
        for (int fd : fds_) ::close(fd);
        fds_.clear();
        return IoError(
            fmt::format("record {}:{}: {}: {}", config.bind_host, port, what, std::strerror(err)));
    };
    for (const auto port : config.ports) {
        const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
        if (fd < 0) throw fail(port, "socket");
        fds_.push_back(fd);
        const int one = 1;
        ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
        if (::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one) != 0)
            throw fail(port, "SO_TIMESTAMPNS");
        ::setsockopt(fd, IPPROTO_IP, IP_PKTINFO, &one, sizeof one);
        ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &config.receive_buffer_bytes,
                     sizeof config.receive_buffer_bytes);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_port = htons(port);
        a.sin_addr = bind_ip;
        if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) throw fail(port, "bind");
        socklen_t len = sizeof a;
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
        ports_.push_back(ntohs(a.sin_port));
    }
    // Create the file now so a bad path fails before anything is received.
    try {
        pcap::Writer probe(config.out);
    } catch (...) {
        for (int fd : fds_) ::close(fd);
        fds_.clear();
        throw;
    }
}

Recorder::~Recorder() {
    for (int fd : fds_) ::close(fd);
}

RecordResult Recorder::run(const std::atomic<bool>& stop,
                           const std::function<void(const RecordStatus&)>& on_status) {
    RecordResult res;
    auto& t = res.totals;
    t.ports = ports_;
    t.packets.assign(ports_.size(), 0);
    t.packets_last.assign(ports_.size(), 0);
    std::vector<std::uint64_t> at_last(ports_.size(), 0);

    std::unique_ptr<pcap::Writer> writer;
    try {
        writer = std::make_unique<pcap::Writer>(config_.out, true);
    } catch (const IoError& e) {
        res.error = e.what();
        return res;
    }
    // The real destination address where bound to 0.0.0.0 comes from IP_PKTINFO.
    in_addr bound{};
    ::inet_pton(AF_INET, config_.bind_host.c_str(), &bound);

    std::vector<std::vector<std::uint8_t>> bufs(kBatch, std::vector<std::uint8_t>(kMaxDatagram));
    std::array<mmsghdr, kBatch> msgs{};
    std::array<iovec, kBatch> iov{};
    std::array<sockaddr_in, kBatch> from{};
    std::array<std::array<char, 256>, kBatch> ctrl{};
    std::vector<pollfd> pfds;
    for (int fd : fds_) pfds.push_back({fd, POLLIN, 0});

    const std::int64_t start = hostclock::monotonic_ns();
    std::int64_t last_flush = start, last_status = start;
    auto fail_write = [&](const std::string& why) {
        res.error = why;
        try {
            writer->close();
        } catch (const IoError&) {
        }
        try {
            res.file_bytes = pcap::cut_to_whole_records(config_.out);
        } catch (const IoError& e) {
            res.error += fmt::format("; {}", e.what());
        }
    };
    TimeOrder order(kOrderHoldNs);
    auto write = [&](const TimeOrder::Record& r) {
        if (writer->write(r.time_ns, r.src, r.dst, r.payload)) ++res.written;
        return true;
    };
    bool failed = false;
    while (!stop.load(std::memory_order_relaxed)) {
        const std::int64_t now = hostclock::monotonic_ns();
        if (config_.duration_ns >= 0 && now - start >= config_.duration_ns) break;
        if (now - last_flush >= config_.flush_interval_ns) {
            last_flush = now;
            try {
                writer->flush();
            } catch (const IoError& e) {
                fail_write(e.what());
                failed = true;
                break;
            }
        }
        if (on_status && now - last_status >= 1'000'000'000) {
            for (std::size_t i = 0; i < ports_.size(); ++i) {
                t.packets_last[i] = t.packets[i] - at_last[i];
                at_last[i] = t.packets[i];
            }
            t.interval_ns = now - last_status;
            last_status = now;
            on_status(t);
        }
        order.release(hostclock::realtime_ns(), false, write);
        if (::poll(pfds.data(), pfds.size(), 50) <= 0) continue;
        for (std::size_t s = 0; s < fds_.size(); ++s) {
            if ((pfds[s].revents & POLLIN) == 0) continue;
            for (std::size_t k = 0; k < kBatch; ++k) {
                iov[k] = {bufs[k].data(), bufs[k].size()};
                msgs[k] = mmsghdr{};
                msgs[k].msg_hdr.msg_name = &from[k];
                msgs[k].msg_hdr.msg_namelen = sizeof(sockaddr_in);
                msgs[k].msg_hdr.msg_iov = &iov[k];
                msgs[k].msg_hdr.msg_iovlen = 1;
                msgs[k].msg_hdr.msg_control = ctrl[k].data();
                msgs[k].msg_hdr.msg_controllen = ctrl[k].size();
            }
            const int n = ::recvmmsg(fds_[s], msgs.data(), kBatch, MSG_DONTWAIT, nullptr);
            for (int k = 0; k < n; ++k) {
                const auto& h = msgs[static_cast<std::size_t>(k)].msg_hdr;
                std::int64_t time_ns = 0;
                in_addr dst = bound;
                auto* mh = const_cast<msghdr*>(&h);
                for (cmsghdr* c = CMSG_FIRSTHDR(mh); c; c = CMSG_NXTHDR(mh, c)) {
                    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
                        timespec ts{};
                        std::memcpy(&ts, CMSG_DATA(c), sizeof ts);
                        time_ns = static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
                    } else if (c->cmsg_level == IPPROTO_IP && c->cmsg_type == IP_PKTINFO) {
                        in_pktinfo pi{};
                        std::memcpy(&pi, CMSG_DATA(c), sizeof pi);
                        dst = pi.ipi_addr;
                    }
                }
                if (time_ns == 0) time_ns = hostclock::realtime_ns();  // no kernel stamp: now
                if (h.msg_flags & MSG_TRUNC) ++res.truncated;
                const auto len = msgs[static_cast<std::size_t>(k)].msg_len;
                const auto& f = from[static_cast<std::size_t>(k)];
                const pcap::Endpoint src{ip_bytes(f.sin_addr), ntohs(f.sin_port)};
                const pcap::Endpoint dsp{ip_bytes(dst), ports_[s]};
                const auto* b = bufs[static_cast<std::size_t>(k)].data();
                order.add({time_ns, src, dsp, std::vector<std::uint8_t>(b, b + len)});
                ++t.packets[s];
                received_.fetch_add(1, std::memory_order_relaxed);
                t.bytes += len;
            }
        }
    }
    order.release(0, true, write);
    res.out_of_order = order.out_of_order();
    if (!failed) {
        try {
            writer->close();
            res.file_bytes = pcap::cut_to_whole_records(config_.out);
        } catch (const IoError& e) {
            fail_write(e.what());
        }
    }
    return res;
}

}  // namespace mirage::replay
