// SPDX-License-Identifier: Apache-2.0
#include "mirage/udp/udp_sender.hpp"

#include <fmt/format.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/multicast.hpp>
#include <boost/asio/ip/udp.hpp>
#include <chrono>
#include <optional>

#include "interfaces.hpp"
#include "mirage/core/error.hpp"

namespace mirage::udp {

namespace asio = boost::asio;
using asio::ip::udp;

namespace {

constexpr std::size_t kStreams = 3;
std::size_t index_of(wire::Stream s) { return static_cast<std::size_t>(s); }
constexpr std::array<const char*, kStreams> kStreamNames = {"data", "position", "imu"};

}  // namespace

DestinationKind classify_destination(const std::array<std::uint8_t, 4>& ip) {
    if ((ip[0] & 0xf0) == 0xe0) return DestinationKind::Multicast;
    if (ip == std::array<std::uint8_t, 4>{255, 255, 255, 255} || detail::is_interface_broadcast(ip))
        return DestinationKind::Broadcast;
    return DestinationKind::Unicast;
}

struct UdpSender::Impl {
    struct Channel {
        std::optional<udp::socket> socket;
        udp::endpoint remote;
        SendCounters counters;
        // Rate-limited failure log: failures since the last line, when that line was printed.
        std::uint64_t unlogged = 0;
        std::chrono::steady_clock::time_point last_log{};
        bool logged_once = false;
    };
    asio::io_context io;
    std::array<Channel, kStreams> channels;
};

UdpSender::UdpSender(const SenderConfig& config) : impl_(new Impl) {
    try {
        boost::system::error_code ec;
        auto address = asio::ip::make_address_v4(config.host, ec);
        if (ec) {
            udp::resolver resolver(impl_->io);
            const auto results = resolver.resolve(udp::v4(), config.host, "", ec);
            if (ec || results.empty())
                throw ConfigError(fmt::format("udp sender: host '{}': cannot resolve: {}",
                                              config.host, ec ? ec.message() : "no IPv4 address"));
            address = results.begin()->endpoint().address().to_v4();
        }
        dest_ip_ = address.to_bytes();
        kind_ = classify_destination(dest_ip_);

        std::optional<asio::ip::address_v4> mcast_if;
        if (kind_ == DestinationKind::Multicast && !config.multicast_interface.empty()) {
            const auto a = detail::interface_address(config.multicast_interface);
            if (!a)
                throw ConfigError(fmt::format(
                    "udp sender: multicast interface '{}': not an IPv4 address or interface name",
                    config.multicast_interface));
            mcast_if = asio::ip::address_v4(*a);
        }
        asio::ip::address_v4 local_address = asio::ip::address_v4::any();
        if (!config.source_address.empty()) {
            local_address = asio::ip::make_address_v4(config.source_address, ec);
            if (ec)
                throw ConfigError(fmt::format("udp sender: source address '{}': {}",
                                              config.source_address, ec.message()));
        }

        for (std::size_t i = 0; i < kStreams; ++i) {
            const auto stream = static_cast<wire::Stream>(i);
            const std::uint16_t port = config.ports.port(stream);
            if (port == 0) continue;
            auto& ch = impl_->channels[i];
            ch.remote = udp::endpoint(address, port);
            const std::string where =
                fmt::format("udp sender {} stream -> {}:{}", kStreamNames[i], config.host, port);
            auto check = [&](const char* what) {
                if (ec) throw IoError(fmt::format("{}: {}: {}", where, what, ec.message()));
            };
            ch.socket.emplace(impl_->io);
            ch.socket->open(udp::v4(), ec);
            check("socket");
            if (kind_ == DestinationKind::Broadcast) {
                ch.socket->set_option(asio::socket_base::broadcast(true), ec);
                check("SO_BROADCAST");
            }
            if (kind_ == DestinationKind::Multicast) {
                ch.socket->set_option(asio::ip::multicast::hops(config.multicast_ttl), ec);
                check("IP_MULTICAST_TTL");
                ch.socket->set_option(asio::ip::multicast::enable_loopback(config.multicast_loop),
                                      ec);
                check("IP_MULTICAST_LOOP");
                if (mcast_if) {
                    ch.socket->set_option(asio::ip::multicast::outbound_interface(*mcast_if), ec);
                    check("IP_MULTICAST_IF");
                }
            }
            if (config.send_buffer_bytes > 0) {
                ch.socket->set_option(asio::socket_base::send_buffer_size(config.send_buffer_bytes),
                                      ec);
                check("SO_SNDBUF");
            }
            const std::uint16_t src_port = config.source_ports.port(stream);
            if (src_port != 0 || !config.source_address.empty()) {
                ch.socket->bind(udp::endpoint(local_address, src_port), ec);
                if (ec)
                    throw IoError(fmt::format("{}: bind {}:{}: {}", where,
                                              local_address.to_string(), src_port, ec.message()));
            }
            // Connected: the kernel then reports ICMP errors (port unreachable) on later sends.
            ch.socket->connect(ch.remote, ec);
            check("connect");
            ch.socket->non_blocking(true, ec);
            check("non-blocking");
        }
    } catch (...) {
        delete impl_;
        throw;
    }
}

UdpSender::~UdpSender() { delete impl_; }

bool UdpSender::send(wire::Stream stream, std::span<const std::uint8_t> bytes) {
    auto& ch = impl_->channels[index_of(stream)];
    if (!ch.socket) {
        ++ch.counters.skipped;
        return false;
    }
    boost::system::error_code ec;
    ch.socket->send(asio::buffer(bytes.data(), bytes.size()), 0, ec);
    if (!ec) {
        ++ch.counters.sent;
        ch.counters.bytes += bytes.size();
        return true;
    }
    ++ch.counters.failed;
    ++ch.unlogged;
    const auto now = std::chrono::steady_clock::now();
    if (!ch.logged_once || now - ch.last_log >= std::chrono::seconds(1)) {
        fmt::print(stderr,
                   "udp sender: {} send(s) to {}:{} failed since the last report ({}); "
                   "{} failed in total, still sending\n",
                   ch.unlogged, ch.remote.address().to_string(), ch.remote.port(), ec.message(),
                   ch.counters.failed);
        ch.unlogged = 0;
        ch.last_log = now;
        ch.logged_once = true;
    }
    return false;
}

const SendCounters& UdpSender::counters(wire::Stream stream) const {
    return impl_->channels[index_of(stream)].counters;
}

SendCounters UdpSender::total() const {
    SendCounters t;
    for (const auto& ch : impl_->channels) {
        t.sent += ch.counters.sent;
        t.failed += ch.counters.failed;
        t.skipped += ch.counters.skipped;
        t.bytes += ch.counters.bytes;
    }
    return t;
}

std::uint16_t UdpSender::local_port(wire::Stream stream) const {
    const auto& ch = impl_->channels[index_of(stream)];
    if (!ch.socket) return 0;
    boost::system::error_code ec;
    const auto ep = ch.socket->local_endpoint(ec);
    return ec ? 0 : ep.port();
}

}  // namespace mirage::udp
