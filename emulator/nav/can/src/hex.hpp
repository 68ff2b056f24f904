// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

// Hex digits shared by the slcan and candump text codecs (internal).
namespace mirage::navcan::detail {

inline constexpr char kHexUpper[] = "0123456789ABCDEF";

inline int hex_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return -1;
}

// 1..8 hex digits, nothing else; false on any other character or an empty/too long text.
inline bool parse_hex(std::string_view s, std::uint32_t& out) {
    if (s.empty() || s.size() > 8) return false;
    std::uint32_t v = 0;
    for (char c : s) {
        const int d = hex_value(c);
        if (d < 0) return false;
        v = (v << 4) | static_cast<std::uint32_t>(d);
    }
    out = v;
    return true;
}

// The low `digits` hex digits of v, most significant first, upper case.
inline void append_hex(std::string& out, std::uint32_t v, int digits) {
    for (int i = digits - 1; i >= 0; --i) out.push_back(kHexUpper[(v >> (4 * i)) & 0xFu]);
}

}  // namespace mirage::navcan::detail
