// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <time.h>

#include <atomic>
#include <cstdint>

namespace mirage::hostclock {

// The host's clocks in integer nanoseconds. CLOCK_MONOTONIC schedules everything real-time
// (pacing, replay, live windows); CLOCK_REALTIME is only read to date things (pcap records,
// candump logs, the fake INS's GPS time). Inline: read once per packet on hot paths (vDSO).
inline std::int64_t monotonic_ns() {
    timespec ts{};
    ::clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}
inline std::int64_t realtime_ns() {
    timespec ts{};
    ::clock_gettime(CLOCK_REALTIME, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// CPU time (user + system) of the whole process so far, in seconds (benchmark and rig CPU
// shares: getrusage).
double process_cpu_seconds();

// Sleeps until an absolute instant of that clock. Absolute deadlines never accumulate delays into
// drift, and a signal restarts the sleep toward the same instant, so it never returns early.
void sleep_until_monotonic(std::int64_t ns);
void sleep_until_realtime(std::int64_t ns);

// Waits until `deadline` (CLOCK_MONOTONIC ns): sleeps until `spin_ns` before it, then spins,
// because a timer wake-up is late by tens of microseconds where a spin is exact. With `stop`,
// sleeps in slices of at most 100 ms and returns false as soon as it is set.
bool wait_until_monotonic(std::int64_t deadline, std::int64_t spin_ns,
                          const std::atomic<bool>* stop = nullptr);

// CLOCK_REALTIME − CLOCK_MONOTONIC, from the tightest of 16 bracketed reads.
std::int64_t realtime_minus_monotonic();

}  // namespace mirage::hostclock
