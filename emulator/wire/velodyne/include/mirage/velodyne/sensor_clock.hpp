// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "mirage/core/time.hpp"

namespace mirage::velodyne {

// The device clock: Velodyne timestamps count µs past the top of the UTC hour (docs/wire-formats.md
// §1.2, §1.9) and wrap at 3 600 000 000.
inline constexpr std::uint32_t kMicrosPerHour = 3'600'000'000u;

// µs past the top of the UTC hour of t (floor).
std::uint32_t micros_past_hour(core::GpsTime t);

// UTC calendar fields of t (what a GPS receiver's $GPRMC reports).
struct UtcFields {
    int year = 1980, month = 1, day = 6;
    int hour = 0, minute = 0, second = 0;
    std::int64_t ns_of_second = 0;
};
UtcFields utc_fields(core::GpsTime t);

}  // namespace mirage::velodyne
