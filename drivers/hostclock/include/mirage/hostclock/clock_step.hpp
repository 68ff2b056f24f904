// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>

namespace mirage::hostclock {

// Follows the steps of a clock that the sensor clock was anchored to (the host's GPS time:
// CLOCK_REALTIME through the leap-second table) against CLOCK_MONOTONIC, which carries the same
// slewing but never steps. `source` returns that clock − CLOCK_MONOTONIC in ns; it is constant
// but for steps (settimeofday, clock_adjtime ADJ_SETOFFSET: a time daemon's first correction).
// The accumulated step is what a device re-syncing to its time source adds to its timestamps
// while its firing schedule runs on (docs/time.md §1). Any thread may poll; one reads the source
// per period.
class ClockStepFollower {
  public:
    using Source = std::function<std::int64_t()>;
    struct Config {
        // A change of source() beyond this is a step; slewing moves both clocks alike and the
        // bracketed read is good to about a microsecond.
        std::int64_t threshold_ns = 100'000;
        std::int64_t period_ns = 100'000'000;  // how often the source is read
    };
    // The base is source() now: the offset the schedule was anchored with.
    ClockStepFollower(Source source, Config config);
    explicit ClockStepFollower(Source source) : ClockStepFollower(std::move(source), Config{}) {}

    // Reads the source if a period has passed since the last read (`monotonic_now`, ns).
    void poll(std::int64_t monotonic_now);

    // ns to add to the timestamps of packets encoded from now on (0 until the first step).
    const std::atomic<std::int64_t>& step() const { return step_; }
    std::uint64_t steps() const { return steps_.load(std::memory_order_relaxed); }

  private:
    Source source_;
    Config config_;
    std::int64_t base_;
    std::atomic<std::int64_t> next_poll_{0};
    std::atomic<std::int64_t> step_{0};
    std::atomic<std::uint64_t> steps_{0};
    std::mutex read_;  // a winner preempted past the next period must not store a stale step
};

}  // namespace mirage::hostclock
