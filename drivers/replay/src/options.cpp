// SPDX-License-Identifier: Apache-2.0
#include "mirage/replay/options.hpp"

#include <fmt/format.h>

#include <charconv>

#include "mirage/core/error.hpp"

namespace mirage::replay {
namespace {

bool parse_port(std::string_view s, std::uint16_t& out) {
    unsigned v = 0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc{} || p != s.data() + s.size() || v > 65535) return false;
    out = static_cast<std::uint16_t>(v);
    return true;
}

}  // namespace

std::map<std::uint16_t, std::uint16_t> parse_port_map(const std::vector<std::string>& items) {
    std::map<std::uint16_t, std::uint16_t> map;
    for (const auto& item : items) {
        const auto eq = item.find('=');
        std::uint16_t from = 0, to = 0;
        if (eq == std::string::npos || !parse_port(std::string_view(item).substr(0, eq), from) ||
            !parse_port(std::string_view(item).substr(eq + 1), to) || to == 0)
            throw ConfigError(fmt::format(
                "replay --port-map '{}': expected CAPTURE_PORT=SEND_PORT, e.g. 2368=12368", item));
        map[from] = to;
    }
    return map;
}

std::int64_t parse_seconds_ns(const std::string& text, const std::string& what) {
    auto fail = [&] {
        return ConfigError(fmt::format("{} '{}': expected seconds, e.g. 1.5", what, text));
    };
    const auto dot = text.find('.');
    const std::string whole = text.substr(0, dot);
    const std::string frac = dot == std::string::npos ? "" : text.substr(dot + 1);
    if ((whole.empty() && frac.empty()) || frac.size() > 9) throw fail();
    std::int64_t s = 0, f = 0;
    if (!whole.empty()) {
        const auto [p, ec] = std::from_chars(whole.data(), whole.data() + whole.size(), s);
        if (ec != std::errc{} || p != whole.data() + whole.size() || s < 0 || s > 9'000'000'000)
            throw fail();
    }
    if (!frac.empty()) {
        const auto [p, ec] = std::from_chars(frac.data(), frac.data() + frac.size(), f);
        if (ec != std::errc{} || p != frac.data() + frac.size() || f < 0) throw fail();
        for (std::size_t i = frac.size(); i < 9; ++i) f *= 10;
    }
    return s * 1'000'000'000 + f;
}

std::vector<std::uint16_t> parse_listen_ports(const std::string& text) {
    std::vector<std::uint16_t> ports;
    std::size_t begin = 0;
    while (begin <= text.size()) {
        auto end = text.find(',', begin);
        if (end == std::string::npos) end = text.size();
        std::string item = text.substr(begin, end - begin);
        const auto colon = item.rfind(':');
        if (colon != std::string::npos) item = item.substr(colon + 1);
        std::uint16_t port = 0;
        if (!parse_port(item, port))
            throw ConfigError(
                fmt::format("record --listen '{}': expected a list like :2368,:8308", text));
        ports.push_back(port);
        begin = end + 1;
    }
    return ports;
}

}  // namespace mirage::replay
