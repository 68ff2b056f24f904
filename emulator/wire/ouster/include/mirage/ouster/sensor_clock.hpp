// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "mirage/core/time.hpp"

namespace mirage::ouster {

// config_params.timestamp_mode (docs/wire-formats.md §2.9, docs/nav-protocols.md).
enum class TimestampMode : std::uint8_t {
    InternalOsc,  // "TIME_FROM_INTERNAL_OSC": ns since power-on
    SyncPulseIn,  // "TIME_FROM_SYNC_PULSE_IN" with a GPS/NMEA source: UTC ns since 1970
    Ptp1588,      // "TIME_FROM_PTP_1588": TAI ns since 1970 (GPS + 19 s)
};
std::string to_string(TimestampMode m);
// The device's names (TIME_FROM_INTERNAL_OSC, …); nullopt for anything else.
std::optional<TimestampMode> parse_timestamp_mode(const std::string& name);

// How the device stamps a GPS instant. Times before power-on read 0 (the counter starts there).
// `step` (when set): ns the time source has stepped since the start, added in the modes that
// follow a source (sync pulse, PTP); the internal oscillator runs on (docs/time.md §1).
struct SensorClock {
    TimestampMode mode = TimestampMode::InternalOsc;
    core::GpsTime power_on{};
    const std::atomic<std::int64_t>* step = nullptr;
    // The step now: read once per packet, so one packet's stamps never straddle a step.
    std::int64_t step_now() const { return step ? step->load(std::memory_order_relaxed) : 0; }
    std::uint64_t ns(core::GpsTime t) const { return ns(t, step_now()); }
    std::uint64_t ns(core::GpsTime t, std::int64_t step_ns) const;
};

}  // namespace mirage::ouster
