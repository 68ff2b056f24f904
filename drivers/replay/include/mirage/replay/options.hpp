// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace mirage::replay {

// "2368=12368" items -> {2368: 12368}. Throws ConfigError naming the bad item.
std::map<std::uint16_t, std::uint16_t> parse_port_map(const std::vector<std::string>& items);
// Decimal seconds ("1.25", "0.000001", "3") -> integer ns without going through a float.
// Throws ConfigError "<what>: ..." for anything else or a negative value.
std::int64_t parse_seconds_ns(const std::string& text, const std::string& what);
// ":2368,:8308" or "2368,127.0.0.1:8308" -> ports (a host part is ignored; see --bind-host).
std::vector<std::uint16_t> parse_listen_ports(const std::string& text);

}  // namespace mirage::replay
