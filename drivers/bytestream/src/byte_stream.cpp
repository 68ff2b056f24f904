// SPDX-License-Identifier: Apache-2.0
// open_byte_stream(): transport URIs (byte_stream.hpp) -> concrete streams.
#include "mirage/bytestream/byte_stream.hpp"

#include <fmt/format.h>

#include <string_view>

#include "mirage/bytestream/uri_query.hpp"
#include "mirage/core/error.hpp"
#include "streams.hpp"

namespace mirage::bytestream {
namespace {

constexpr std::string_view kComponent = "byte stream";

[[noreturn]] void bad(const std::string& uri, const std::string& why) {
    throw ConfigError(fmt::format("{} '{}': {}", kComponent, uri, why));
}

struct HostPort {
    std::string host;
    std::uint16_t port = 0;
};

// "host:port", ":port", "[v6]:port".
HostPort split_host_port(const std::string& uri, std::string_view text) {
    HostPort hp;
    std::string_view port_text;
    if (!text.empty() && text.front() == '[') {
        const auto close = text.find(']');
        if (close == std::string_view::npos || close + 1 >= text.size() || text[close + 1] != ':')
            bad(uri, "expected [ipv6-address]:port");
        hp.host = std::string(text.substr(1, close - 1));
        port_text = text.substr(close + 2);
    } else {
        const auto colon = text.rfind(':');
        if (colon == std::string_view::npos) bad(uri, "expected host:port");
        hp.host = std::string(text.substr(0, colon));
        if (hp.host.find(':') != std::string::npos) bad(uri, "IPv6 addresses go in brackets");
        port_text = text.substr(colon + 1);
    }
    const auto port = parse_unsigned(port_text);
    if (!port || *port > 65535)
        bad(uri, fmt::format("port '{}' is not a number in 0..65535", port_text));
    hp.port = static_cast<std::uint16_t>(*port);
    return hp;
}

detail::SerialOptions parse_serial(const std::string& uri, std::size_t prefix) {
    const UriQuery q = parse_uri_query(kComponent, uri);
    q.check_keys(kComponent, uri, "baud,bits,parity,stop");
    detail::SerialOptions o;
    o.path = q.head.substr(prefix);
    if (o.path.empty()) bad(uri, "no device path");
    if (const auto baud = q.number(kComponent, uri, "baud", 1, 4'000'000)) {
        if (!detail::serial_baud_supported(static_cast<std::uint32_t>(*baud)))
            bad(uri, fmt::format("baud={} has no termios speed (e.g. 9600, 115200, 921600)", *baud));
        o.baud = static_cast<std::uint32_t>(*baud);
    }
    if (const auto bits = q.number(kComponent, uri, "bits", 5, 8)) o.bits = static_cast<int>(*bits);
    if (const auto stop = q.number(kComponent, uri, "stop", 1, 2)) o.stop = static_cast<int>(*stop);
    if (q.has("parity")) {
        const std::string& p = q.items.at("parity");
        if (p == "none" || p == "n" || p == "N")
            o.parity = detail::Parity::None;
        else if (p == "even" || p == "e" || p == "E")
            o.parity = detail::Parity::Even;
        else if (p == "odd" || p == "o" || p == "O")
            o.parity = detail::Parity::Odd;
        else
            bad(uri, fmt::format("parity='{}': expected none, even or odd", p));
    }
    return o;
}

}  // namespace

std::unique_ptr<ByteStream> open_byte_stream(const std::string& uri) {
    const std::string_view u = uri;
    if (u.empty()) bad(uri, "empty URI");
    if (u.starts_with("tcp://")) {
        const UriQuery q = parse_uri_query(kComponent, uri);
        q.check_keys(kComponent, uri, "");
        const HostPort hp = split_host_port(uri, std::string_view(q.head).substr(6));
        if (hp.host.empty()) bad(uri, "a TCP client needs a host");
        if (hp.port == 0) bad(uri, "a TCP client needs a port other than 0");
        return detail::open_tcp_client(hp.host, hp.port);
    }
    if (u.starts_with("udp://")) {
        const UriQuery q = parse_uri_query(kComponent, uri);
        q.check_keys(kComponent, uri, "send");
        const HostPort hp = split_host_port(uri, std::string_view(q.head).substr(6));
        if (q.has("send")) {
            if (!q.items.at("send").empty()) bad(uri, "'send' takes no value");
            if (hp.host.empty() || hp.port == 0) bad(uri, "a UDP sender needs host and port");
            return detail::open_udp_sender(hp.host, hp.port);
        }
        return detail::open_udp_receiver(hp.host, hp.port);
    }
    if (u.starts_with("serial:")) return detail::open_serial(parse_serial(uri, 7));
    if (u.front() == '/') return detail::open_serial(parse_serial(uri, 0));
    bad(uri, "unknown transport (expected /dev/..., serial:/dev/..., tcp://host:port, "
             "udp://[host]:port[?send])");
}

}  // namespace mirage::bytestream
