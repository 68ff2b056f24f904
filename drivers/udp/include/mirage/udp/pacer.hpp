// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "mirage/core/time.hpp"
#include "mirage/udp/lateness_histogram.hpp"

namespace mirage::udp {

struct PacerConfig {
    bool as_fast_as_possible = false;     // never wait (benchmarks, file output)
    core::Nanos spin_margin{50'000};      // sleep until this long before the deadline, then spin
    core::Nanos late_threshold{100'000};  // what counts as "late" in the statistics
};

// Releases packets at host times that follow the sensor clock: deadline = t0_host + (t_sensor −
// t0_sensor), each computed from the anchor (absolute deadlines), so sleep errors never
// accumulate into drift. Sleeps with clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME) to
// spin_margin before the deadline, then spins on the clock for the last microseconds.
class Pacer {
  public:
    explicit Pacer(PacerConfig config = {});

    // Ties sensor time t0 to host CLOCK_MONOTONIC time host_ns. Without it the first wait()
    // anchors the sensor time it is given to "now".
    void anchor(core::GpsTime t0_sensor, std::int64_t host_monotonic_ns);
    bool anchored() const { return anchored_; }

    // Blocks until the host deadline of t_sensor (returns at once if it has passed or in
    // as-fast-as-possible mode) and returns the lateness now − deadline, also recorded in
    // stats(). Never throws.
    core::Nanos wait(core::GpsTime t_sensor);

    // CLOCK_MONOTONIC deadline of a sensor time (anchor required).
    std::int64_t deadline_ns(core::GpsTime t_sensor) const;
    const LatenessHistogram& stats() const { return stats_; }
    const PacerConfig& config() const { return config_; }

  private:
    PacerConfig config_;
    bool anchored_ = false;
    core::GpsTime t0_sensor_{};
    std::int64_t t0_host_ns_ = 0;
    LatenessHistogram stats_;
};

}  // namespace mirage::udp
