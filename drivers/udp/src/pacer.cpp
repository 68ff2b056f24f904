// SPDX-License-Identifier: Apache-2.0
#include "mirage/udp/pacer.hpp"

#include <sys/prctl.h>

#include <cerrno>
#include <ctime>

#include "mirage/hostclock/host_clock.hpp"

namespace mirage::udp {
namespace {

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

void Pacer::anchor(core::GpsTime t0_sensor, std::int64_t host_monotonic_ns) {
    t0_sensor_ = t0_sensor;
    t0_host_ns_ = host_monotonic_ns;
    anchored_ = true;
}

std::int64_t Pacer::deadline_ns(core::GpsTime t_sensor) const {
    return t0_host_ns_ + (t_sensor - t0_sensor_).count();
}

core::Nanos Pacer::wait(core::GpsTime t_sensor) {
    if (!anchored_) anchor(t_sensor, hostclock::monotonic_ns());
    if (config_.as_fast_as_possible) {
        stats_.add(core::Nanos{0});
        return core::Nanos{0};
    }
    tighten_timer_slack();
    const std::int64_t deadline = deadline_ns(t_sensor);
    // The last ~50 µs are spun: timer slack is larger.
    hostclock::wait_until_monotonic(deadline, config_.spin_margin.count());
    const core::Nanos lateness{hostclock::monotonic_ns() - deadline};
    stats_.add(lateness);
    return lateness;
}

}  // namespace mirage::udp
