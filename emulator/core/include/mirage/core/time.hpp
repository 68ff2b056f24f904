// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <chrono>
#include <cstdint>
#include <string>

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

// UTC (Unix ns, POSIX: leap seconds not counted) <-> GPS time.
GpsTime gps_from_unix_ns(std::int64_t unix_ns);
std::int64_t unix_ns_from_gps(GpsTime t);

// GPS week number and nanoseconds into the week.
struct GpsWeekTime {
    std::int32_t week;
    std::int64_t ns_of_week;
};
GpsWeekTime to_week_time(GpsTime t);
GpsTime from_week_time(std::int32_t week, std::int64_t ns_of_week);

// LAS "adjusted standard GPS time": GPS seconds − 1e9 (LAS 1.4 global encoding bit 0).
// The only place a time becomes a double, at the file boundary.
double adjusted_standard_gps_seconds(GpsTime t);

// Parses "2024-01-01T00:00:00Z" / "2024-01-01 00:00:00" (UTC) or "gps:<seconds>" into GPS time.
// Throws ConfigError naming the text.
GpsTime parse_time(const std::string& text);

}  // namespace mirage::core
