// SPDX-License-Identifier: Apache-2.0
#include <arpa/inet.h>
#include <fmt/format.h>

#include <charconv>

#include "mirage/control/modbus_server.hpp"
#include "mirage/core/error.hpp"

namespace mirage::control {

void parse_tcp_address(const std::string& text, ControlEndpoint& e) {
    const auto bad = [&](const char* why) {
        return ConfigError(fmt::format("control: tcp '{}': {}", text, why));
    };
    const auto colon = text.rfind(':');
    if (colon == std::string::npos) throw bad("expected host:port (e.g. 127.0.0.1:1502)");
    std::string host = text.substr(0, colon);
    if (host == "localhost") host = "127.0.0.1";
    in_addr a{};
    if (inet_pton(AF_INET, host.c_str(), &a) != 1) throw bad("host is not a dotted IPv4 address");
    int port = -1;
    const char* p = text.data() + colon + 1;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(p, end, port);
    if (ec != std::errc{} || ptr != end || port < 0 || port > 65535)
        throw bad("port is not a number in 0..65535");
    e.tcp_host = host;
    e.tcp_port = port;
}

}  // namespace mirage::control
