// SPDX-License-Identifier: Apache-2.0
#include "mirage/udp/pacer.hpp"

#include <sys/prctl.h>

#include <cerrno>
#include <ctime>

namespace mirage::udp {
namespace {

timespec to_timespec(std::int64_t ns) {
    timespec ts{};
    ts.tv_sec = static_cast<time_t>(ns / 1'000'000'000);
    ts.tv_nsec = static_cast<long>(ns % 1'000'000'000);
    return ts;
}

// Linux delays timer wake-ups by up to the thread's timer slack (50 µs by default), which would
// eat the whole spin margin; 1 ns asks for the earliest wake-up. Per thread, set once.
void tighten_timer_slack() {
    thread_local bool done = false;
    if (!done) {
        prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
        done = true;
    }
}

}  // namespace

Pacer::Pacer(PacerConfig config) : config_(config), stats_(config.late_threshold) {}

std::int64_t Pacer::monotonic_ns() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void Pacer::anchor(core::GpsTime t0_sensor, std::int64_t host_monotonic_ns) {
    t0_sensor_ = t0_sensor;
    t0_host_ns_ = host_monotonic_ns;
    anchored_ = true;
}

std::int64_t Pacer::deadline_ns(core::GpsTime t_sensor) const {
    return t0_host_ns_ + (t_sensor - t0_sensor_).count();
}

core::Nanos Pacer::wait(core::GpsTime t_sensor) {
    if (!anchored_) anchor(t_sensor, monotonic_ns());
    if (config_.as_fast_as_possible) {
        stats_.add(core::Nanos{0});
        return core::Nanos{0};
    }
    tighten_timer_slack();
    const std::int64_t deadline = deadline_ns(t_sensor);
    const std::int64_t wake = deadline - config_.spin_margin.count();
    if (monotonic_ns() < wake) {
        const timespec ts = to_timespec(wake);
        // Absolute sleep: a signal restarts it toward the same instant.
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
        }
    }
    std::int64_t now = monotonic_ns();
    while (now < deadline) now = monotonic_ns();  // the last ~50 µs: timer slack is larger
    const core::Nanos lateness{now - deadline};
    stats_.add(lateness);
    return lateness;
}

}  // namespace mirage::udp
