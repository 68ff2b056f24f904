// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace mirage::udp::detail {

// IPv4 address of a dotted quad, or of the host's interface with that name (getifaddrs).
std::optional<std::array<std::uint8_t, 4>> interface_address(const std::string& text);
// True when ip is the directed broadcast address (addr | ~mask) of one of the host's interfaces.
bool is_interface_broadcast(const std::array<std::uint8_t, 4>& ip);

}  // namespace mirage::udp::detail
