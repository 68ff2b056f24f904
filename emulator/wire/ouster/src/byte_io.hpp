// SPDX-License-Identifier: Apache-2.0
#pragma once
// Little-endian field access (all Ouster fields are little-endian). Callers check bounds.
#include <cstddef>
#include <cstdint>

namespace mirage::ouster {

inline void put_uint(std::uint8_t* p, std::uint64_t v, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
inline std::uint64_t get_uint(const std::uint8_t* p, std::size_t n) {
    std::uint64_t v = 0;
    for (std::size_t i = 0; i < n; ++i) v |= std::uint64_t{p[i]} << (8 * i);
    return v;
}
inline void put_u16(std::uint8_t* p, std::uint16_t v) { put_uint(p, v, 2); }
inline void put_u32(std::uint8_t* p, std::uint32_t v) { put_uint(p, v, 4); }
inline void put_u64(std::uint8_t* p, std::uint64_t v) { put_uint(p, v, 8); }
inline std::uint16_t get_u16(const std::uint8_t* p) {
    return static_cast<std::uint16_t>(get_uint(p, 2));
}
inline std::uint32_t get_u32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(get_uint(p, 4));
}
inline std::uint64_t get_u64(const std::uint8_t* p) { return get_uint(p, 8); }

}  // namespace mirage::ouster
