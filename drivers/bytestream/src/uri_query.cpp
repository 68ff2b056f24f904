// SPDX-License-Identifier: Apache-2.0
#include "mirage/bytestream/uri_query.hpp"

#include <fmt/format.h>

#include <limits>

#include "mirage/core/error.hpp"

namespace mirage::bytestream {

std::optional<std::uint64_t> parse_unsigned(std::string_view text) {
    if (text.empty() || text.size() > 20) return std::nullopt;
    std::uint64_t v = 0;
    for (char c : text) {
        if (c < '0' || c > '9') return std::nullopt;
        const auto d = static_cast<std::uint64_t>(c - '0');
        if (v > (std::numeric_limits<std::uint64_t>::max() - d) / 10) return std::nullopt;
        v = v * 10 + d;
    }
    return v;
}

UriQuery parse_uri_query(std::string_view component, std::string_view uri) {
    UriQuery q;
    const auto qpos = uri.find('?');
    q.head = std::string(uri.substr(0, qpos));
    if (qpos == std::string_view::npos) return q;
    std::string_view rest = uri.substr(qpos + 1);
    while (true) {
        const auto amp = rest.find('&');
        const std::string_view item = rest.substr(0, amp);
        const auto eq = item.find('=');
        const std::string key(item.substr(0, eq));
        const std::string value = eq == std::string_view::npos ? "" : std::string(item.substr(eq + 1));
        if (key.empty())
            throw ConfigError(fmt::format("{} '{}': empty option name in the query", component, uri));
        if (!q.items.emplace(key, value).second)
            throw ConfigError(fmt::format("{} '{}': option '{}' given twice", component, uri, key));
        if (amp == std::string_view::npos) break;
        rest = rest.substr(amp + 1);
    }
    return q;
}

void UriQuery::check_keys(std::string_view component, std::string_view uri,
                          std::string_view allowed) const {
    for (const auto& [key, value] : items) {
        bool ok = false;
        std::string_view rest = allowed;
        while (!ok) {
            const auto comma = rest.find(',');
            if (rest.substr(0, comma) == key) ok = true;
            if (comma == std::string_view::npos) break;
            rest = rest.substr(comma + 1);
        }
        if (!ok)
            throw ConfigError(fmt::format("{} '{}': unknown option '{}' (expected {})", component,
                                          uri, key, allowed.empty() ? "none" : allowed));
    }
}

std::optional<std::uint64_t> UriQuery::number(std::string_view component, std::string_view uri,
                                              const std::string& key, std::uint64_t lo,
                                              std::uint64_t hi) const {
    const auto it = items.find(key);
    if (it == items.end()) return std::nullopt;
    const auto v = parse_unsigned(it->second);
    if (!v || *v < lo || *v > hi)
        throw ConfigError(fmt::format("{} '{}': {}='{}': expected a whole number in {}..{}",
                                      component, uri, key, it->second, lo, hi));
    return v;
}

}  // namespace mirage::bytestream
