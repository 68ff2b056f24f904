// SPDX-License-Identifier: Apache-2.0
#include "mirage/hostclock/clock_step.hpp"

#include <utility>

namespace mirage::hostclock {

ClockStepFollower::ClockStepFollower(Source source, Config config)
    : source_(std::move(source)), config_(config), base_(source_()) {}

void ClockStepFollower::poll(std::int64_t monotonic_now) {
    std::int64_t due = next_poll_.load(std::memory_order_relaxed);
    // One thread wins the period; the others go on encoding.
    if (monotonic_now < due ||
        !next_poll_.compare_exchange_strong(due, monotonic_now + config_.period_ns,
                                            std::memory_order_relaxed))
        return;
    const std::lock_guard lock(read_);
    const std::int64_t now_step = source_() - base_;
    const std::int64_t old = step_.load(std::memory_order_relaxed);
    const std::int64_t change = now_step - old;
    if (change > config_.threshold_ns || change < -config_.threshold_ns) {
        step_.store(now_step, std::memory_order_relaxed);
        steps_.fetch_add(1, std::memory_order_relaxed);
    }
}

}  // namespace mirage::hostclock
