// SPDX-License-Identifier: Apache-2.0
#include "mirage/ouster/sensor_clock.hpp"

namespace mirage::ouster {

std::string to_string(TimestampMode m) {
    switch (m) {
        case TimestampMode::InternalOsc:
            return "TIME_FROM_INTERNAL_OSC";
        case TimestampMode::SyncPulseIn:
            return "TIME_FROM_SYNC_PULSE_IN";
        case TimestampMode::Ptp1588:
            return "TIME_FROM_PTP_1588";
    }
    return "TIME_FROM_INTERNAL_OSC";
}

std::optional<TimestampMode> parse_timestamp_mode(const std::string& name) {
    for (TimestampMode m :
         {TimestampMode::InternalOsc, TimestampMode::SyncPulseIn, TimestampMode::Ptp1588})
        if (name == to_string(m)) return m;
    return std::nullopt;
}

std::uint64_t SensorClock::ns(core::GpsTime t, std::int64_t step_ns) const {
    if (mode != TimestampMode::InternalOsc) t += core::Nanos(step_ns);
    switch (mode) {
        case TimestampMode::InternalOsc: {
            const auto d = (t - power_on).count();
            return d > 0 ? static_cast<std::uint64_t>(d) : 0;
        }
        case TimestampMode::SyncPulseIn: {
            const auto u = core::unix_ns_from_gps(t);
            return u > 0 ? static_cast<std::uint64_t>(u) : 0;
        }
        case TimestampMode::Ptp1588: {
            // TAI = GPS + 19 s; the PTP epoch is 1970-01-01 TAI.
            constexpr std::int64_t kTaiMinusGpsS = 19;
            const auto v = t.time_since_epoch().count() +
                           (core::kGpsEpochUnixSeconds + kTaiMinusGpsS) * core::kNsPerSecond;
            return v > 0 ? static_cast<std::uint64_t>(v) : 0;
        }
    }
    return 0;
}

}  // namespace mirage::ouster
