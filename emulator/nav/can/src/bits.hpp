// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cmath>
#include <cstdint>

// Intel (little-endian) CAN signal packing and calendar arithmetic shared by the codecs
// (internal).
namespace mirage::navcan::detail {

using Bytes8 = std::array<std::uint8_t, 8>;

// Unsigned Intel signal: `length` bits from `start` (bit 0 = LSB of byte 0). Caller keeps
// start + length <= 64.
inline std::uint64_t get_u(const Bytes8& d, unsigned start, unsigned length) {
    std::uint64_t raw = 0;
    for (unsigned i = 0; i < 8; ++i) raw |= static_cast<std::uint64_t>(d[i]) << (8 * i);
    raw >>= start;
    if (length < 64) raw &= (std::uint64_t{1} << length) - 1;
    return raw;
}

inline std::int64_t get_s(const Bytes8& d, unsigned start, unsigned length) {
    const std::uint64_t u = get_u(d, start, length);
    if (length < 64 && (u >> (length - 1)) != 0) {
        return static_cast<std::int64_t>(u | ~((std::uint64_t{1} << length) - 1));
    }
    return static_cast<std::int64_t>(u);
}

inline void put(Bytes8& d, unsigned start, unsigned length, std::uint64_t value) {
    for (unsigned i = 0; i < length; ++i) {
        const unsigned bit = start + i;
        const auto mask = static_cast<std::uint8_t>(1u << (bit % 8));
        if ((value >> i) & 1u) {
            d[bit / 8] = static_cast<std::uint8_t>(d[bit / 8] | mask);
        } else {
            d[bit / 8] = static_cast<std::uint8_t>(d[bit / 8] & ~mask);
        }
    }
}

// Physical value -> raw integer by rounding to the nearest step, saturated to the signal's
// range (the units saturate rather than wrap); NaN gives 0.
inline std::int64_t to_raw(double physical, double factor, std::int64_t lo, std::int64_t hi) {
    if (!std::isfinite(physical)) return physical > 0 ? hi : (physical < 0 ? lo : 0);
    const double r = std::round(physical / factor);
    if (r <= static_cast<double>(lo)) return lo;
    if (r >= static_cast<double>(hi)) return hi;
    return static_cast<std::int64_t>(r);
}

inline void put_s(Bytes8& d, unsigned start, unsigned length, double physical, double factor) {
    const std::int64_t hi = (std::int64_t{1} << (length - 1)) - 1;
    put(d, start, length, static_cast<std::uint64_t>(to_raw(physical, factor, -hi - 1, hi)));
}

inline void put_u(Bytes8& d, unsigned start, unsigned length, double physical, double factor) {
    const std::int64_t hi = static_cast<std::int64_t>((std::uint64_t{1} << length) - 1);
    put(d, start, length, static_cast<std::uint64_t>(to_raw(physical, factor, 0, hi)));
}

// Days from 1970-01-01 to a proleptic Gregorian date (Howard Hinnant's civil algorithm).
inline std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
    y -= m <= 2 ? 1 : 0;
    const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
    const auto yoe = static_cast<unsigned>(y - era * 400);
    const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
    const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

struct Civil {
    std::int64_t year;
    unsigned month, day;
};
inline Civil civil_from_days(std::int64_t z) {
    z += 719468;
    const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
    const auto doe = static_cast<unsigned>(z - era * 146097);
    const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    const unsigned mp = (5 * doy + 2) / 153;
    const unsigned d = doy - (153 * mp + 2) / 5 + 1;
    const unsigned m = mp < 10 ? mp + 3 : mp - 9;
    return {static_cast<std::int64_t>(yoe) + era * 400 + (m <= 2 ? 1 : 0), m, d};
}

inline bool valid_date(std::int64_t y, unsigned m, unsigned d) {
    static constexpr unsigned kDays[] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    if (m < 1 || m > 12 || d < 1 || d > kDays[m - 1]) return false;
    const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    return !(m == 2 && d == 29 && !leap);
}

}  // namespace mirage::navcan::detail
