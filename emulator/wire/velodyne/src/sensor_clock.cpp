// SPDX-License-Identifier: Apache-2.0
#include "mirage/velodyne/sensor_clock.hpp"

#include <chrono>

namespace mirage::velodyne {
namespace {

std::int64_t floor_mod(std::int64_t a, std::int64_t m) {
    const std::int64_t r = a % m;
    return r < 0 ? r + m : r;
}

}  // namespace

std::uint32_t micros_past_hour(core::GpsTime t) {
    constexpr std::int64_t kNsPerHour = 3'600LL * core::kNsPerSecond;
    return static_cast<std::uint32_t>(floor_mod(core::unix_ns_from_gps(t), kNsPerHour) / 1000);
}

UtcFields utc_fields(core::GpsTime t) {
    const std::int64_t unix_ns = core::unix_ns_from_gps(t);
    const std::int64_t ns = floor_mod(unix_ns, core::kNsPerSecond);
    const std::int64_t secs = (unix_ns - ns) / core::kNsPerSecond;
    const std::int64_t sod = floor_mod(secs, 86'400);
    const std::int64_t days = (secs - sod) / 86'400;
    const std::chrono::year_month_day ymd{
        std::chrono::sys_days{std::chrono::days{static_cast<int>(days)}}};
    UtcFields f;
    f.year = static_cast<int>(ymd.year());
    f.month = static_cast<int>(static_cast<unsigned>(ymd.month()));
    f.day = static_cast<int>(static_cast<unsigned>(ymd.day()));
    f.hour = static_cast<int>(sod / 3600);
    f.minute = static_cast<int>(sod / 60 % 60);
    f.second = static_cast<int>(sod % 60);
    f.ns_of_second = ns;
    return f;
}

}  // namespace mirage::velodyne
