// SPDX-License-Identifier: Apache-2.0
#include "interfaces.hpp"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>

#include <cstring>

namespace mirage::udp::detail {
namespace {

std::array<std::uint8_t, 4> bytes_of(std::uint32_t network_order) {
    std::array<std::uint8_t, 4> b{};
    std::memcpy(b.data(), &network_order, 4);
    return b;
}

// Calls fn(ifaddrs&) for every IPv4 interface address; stops when fn returns true.
template <class Fn>
bool any_ipv4_interface(Fn fn) {
    ifaddrs* list = nullptr;
    if (getifaddrs(&list) != 0) return false;
    bool found = false;
    for (ifaddrs* a = list; a != nullptr && !found; a = a->ifa_next)
        if (a->ifa_addr != nullptr && a->ifa_addr->sa_family == AF_INET) found = fn(*a);
    freeifaddrs(list);
    return found;
}

std::uint32_t in4(const sockaddr* sa) {
    sockaddr_in sin{};
    std::memcpy(&sin, sa, sizeof sin);
    return sin.sin_addr.s_addr;
}

}  // namespace

std::optional<std::array<std::uint8_t, 4>> interface_address(const std::string& text) {
    in_addr addr{};
    if (inet_pton(AF_INET, text.c_str(), &addr) == 1) return bytes_of(addr.s_addr);
    std::optional<std::array<std::uint8_t, 4>> result;
    any_ipv4_interface([&](const ifaddrs& a) {
        if (text != a.ifa_name) return false;
        result = bytes_of(in4(a.ifa_addr));
        return true;
    });
    return result;
}

bool is_interface_broadcast(const std::array<std::uint8_t, 4>& ip) {
    std::uint32_t target = 0;
    std::memcpy(&target, ip.data(), 4);
    return any_ipv4_interface([&](const ifaddrs& a) {
        if (a.ifa_netmask == nullptr) return false;
        const std::uint32_t mask = in4(a.ifa_netmask);
        // /31 and /32 have no broadcast address (RFC 3021).
        if (ntohl(mask) >= 0xfffffffeu) return false;
        return (in4(a.ifa_addr) | ~mask) == target;
    });
}

}  // namespace mirage::udp::detail
