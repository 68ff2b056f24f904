// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace mirage::bytestream {

// "<head>?k=v&k2=v2&flag" split into the head and its keys. Shared by the byte-stream and
// CAN-bus URIs so both reject the same mistakes the same way.
struct UriQuery {
    std::string head;                          // text before '?'
    std::map<std::string, std::string> items;  // "flag" without '=' maps to ""

    // Throws ConfigError "<component> '<uri>': unknown option 'x' (expected a, b)" when a key
    // is not in `allowed` (comma-separated names).
    void check_keys(std::string_view component, std::string_view uri,
                    std::string_view allowed) const;
    // The value of `key` as an unsigned decimal in [lo, hi], or nullopt when absent; throws
    // ConfigError naming the URI and the key when it is not such a number.
    std::optional<std::uint64_t> number(std::string_view component, std::string_view uri,
                                        const std::string& key, std::uint64_t lo,
                                        std::uint64_t hi) const;
    bool has(const std::string& key) const { return items.count(key) != 0; }
};

// Throws ConfigError "<component> '<uri>': ..." on an empty key or a repeated key.
UriQuery parse_uri_query(std::string_view component, std::string_view uri);

// Unsigned decimal with no sign, spaces or suffix; nullopt on anything else or overflow.
std::optional<std::uint64_t> parse_unsigned(std::string_view text);

}  // namespace mirage::bytestream
