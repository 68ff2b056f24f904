// SPDX-License-Identifier: Apache-2.0
#include "mirage/hostclock/host_clock.hpp"

#include <sys/resource.h>

#include <cerrno>
#include <cstdint>

namespace mirage::hostclock {

double process_cpu_seconds() {
    rusage ru{};
    ::getrusage(RUSAGE_SELF, &ru);
    const auto tv = [](const timeval& t) { return double(t.tv_sec) + double(t.tv_usec) / 1e6; };
    return tv(ru.ru_utime) + tv(ru.ru_stime);
}
namespace {

void sleep_until(clockid_t clock, std::int64_t ns) {
    const timespec ts{static_cast<time_t>(ns / 1'000'000'000),
                      static_cast<long>(ns % 1'000'000'000)};
    while (::clock_nanosleep(clock, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
}

}  // namespace

void sleep_until_monotonic(std::int64_t ns) { sleep_until(CLOCK_MONOTONIC, ns); }
void sleep_until_realtime(std::int64_t ns) { sleep_until(CLOCK_REALTIME, ns); }

bool wait_until_monotonic(std::int64_t deadline, std::int64_t spin_ns,
                          const std::atomic<bool>* stop) {
    constexpr std::int64_t kSlice = 100'000'000;
    for (;;) {
        const std::int64_t now = monotonic_ns();
        if (now >= deadline) return true;
        if (stop && stop->load(std::memory_order_relaxed)) return false;
        std::int64_t wake = deadline - spin_ns;
        if (stop && wake > now + kSlice) wake = now + kSlice;
        if (wake > now) {
            sleep_until_monotonic(wake);
            continue;
        }
        while (monotonic_ns() < deadline) {
        }
        return true;
    }
}

std::int64_t realtime_minus_monotonic() {
    std::int64_t best_gap = INT64_MAX, offset = 0;
    for (int i = 0; i < 16; ++i) {
        const std::int64_t m0 = monotonic_ns();
        const std::int64_t r = realtime_ns();
        const std::int64_t m1 = monotonic_ns();
        if (m1 - m0 < best_gap) {
            best_gap = m1 - m0;
            offset = r - (m0 + (m1 - m0) / 2);
        }
    }
    return offset;
}

}  // namespace mirage::hostclock
