// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace mirage::core {

// One timeline for the whole program: integer nanoseconds since the GPS epoch
// (1980-01-06T00:00:00 UTC), GPS time scale (no leap seconds). Never float seconds.
struct GpsClock {
    using rep = std::int64_t;
    using period = std::nano;
    using duration = std::chrono::nanoseconds;
    using time_point = std::chrono::time_point<GpsClock, duration>;
    static constexpr bool is_steady = true;
};
using GpsTime = GpsClock::time_point;
using Nanos = std::chrono::nanoseconds;

inline constexpr std::int64_t kNsPerSecond = 1'000'000'000;
inline constexpr std::int64_t kSecondsPerWeek = 604'800;
// Seconds between the Unix epoch and the GPS epoch (ignoring leap seconds).
inline constexpr std::int64_t kGpsEpochUnixSeconds = 315'964'800;

// GPS − UTC in seconds at a UTC instant given as Unix seconds (leap-second table; 18 since 2017).
int leap_seconds_at_utc(std::int64_t unix_seconds);
// GPS − UTC in seconds at a GPS instant.
int leap_seconds_at_gps(GpsTime t);

// UTC (Unix ns, POSIX: leap seconds not counted) <-> GPS time. An inserted leap second
// (23:59:60) has no POSIX number; unix_ns_from_gps maps it onto the following 00:00:00.
GpsTime gps_from_unix_ns(std::int64_t unix_ns);
std::int64_t unix_ns_from_gps(GpsTime t);

// GPS week number and nanoseconds into the week.
struct GpsWeekTime {
    std::int32_t week;
    std::int64_t ns_of_week;
};
GpsWeekTime to_week_time(GpsTime t);
// The last GPS week whose every instant fits the int64 ns timeline (year 2272). Decoders refuse
// larger weeks read from the wire; from_week_time requires 0 <= week <= kMaxGpsWeek and
// 0 <= ns_of_week < one week.
inline constexpr std::int32_t kMaxGpsWeek = 15'249;
GpsTime from_week_time(std::int32_t week, std::int64_t ns_of_week);

// LAS "adjusted standard GPS time": GPS seconds − 1e9 (LAS 1.4 global encoding bit 0).
// The only place a time becomes a double, at the file boundary. Inline: the LAS encoder calls
// it once per point. Split before converting so the result is the correctly rounded value of the
// exact decimal (whole seconds and the fraction are each exact in a double).
inline double adjusted_standard_gps_seconds(GpsTime t) {
    constexpr std::int64_t kNs = 1'000'000'000;
    const std::int64_t d = t.time_since_epoch().count() - 1'000'000'000 * kNs;
    std::int64_t s = d / kNs, frac = d % kNs;
    if (frac < 0) {  // floor division
        --s;
        frac += kNs;
    }
    return static_cast<double>(s) + static_cast<double>(frac) * 1e-9;
}

// Parses "2024-01-01T00:00:00Z" / "2024-01-01 00:00:00" (UTC) or "gps:<seconds>" into GPS time.
// UTC forms take an optional fraction of up to 9 digits ("...:00.123456789Z"), read exactly,
// and second 60 at an inserted leap second; years 1900..2200. Throws ConfigError naming the text.
GpsTime parse_time(const std::string& text);

// Exact decimal seconds -> ns: "[-]digits[.digits]" with at most 9 significant decimal places
// (further digits must be zeros). No exponent, no float rounding. nullopt on anything else
// or on int64 overflow. "1388534418.000000123" -> 1388534418000000123 ns.
std::optional<Nanos> parse_decimal_seconds(std::string_view text);
// Inverse of parse_decimal_seconds: "<seconds>.<9 digits>", exact ("-0.500000000" for −0.5 s).
std::string format_decimal_seconds(Nanos d);

}  // namespace mirage::core
