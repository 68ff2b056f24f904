// SPDX-License-Identifier: Apache-2.0
// ClockStepFollower (docs/time.md §1): a step of the followed clock against CLOCK_MONOTONIC is
// taken up at the next poll after a period; changes within the threshold are not steps; one
// source read per period however many threads poll.
#include "mirage/hostclock/clock_step.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

namespace {

using mirage::hostclock::ClockStepFollower;

struct FakeClock {
    std::atomic<std::int64_t> offset{1'000'000'000'000};  // the followed clock − monotonic
    std::atomic<int> reads{0};
    ClockStepFollower::Source source() {
        return [this] {
            reads.fetch_add(1);
            return offset.load();
        };
    }
};

constexpr ClockStepFollower::Config kCfg{100'000, 100'000'000};

TEST(ClockStepFollower, StepTakenAtTheNextPeriod) {
    FakeClock c;
    ClockStepFollower f(c.source(), kCfg);
    f.poll(0);
    EXPECT_EQ(f.step().load(), 0);
    c.offset += 2'500'000'000;  // settimeofday(+2.5 s)
    f.poll(50'000'000);         // within the period: not read
    EXPECT_EQ(f.step().load(), 0);
    f.poll(100'000'000);
    EXPECT_EQ(f.step().load(), 2'500'000'000);
    EXPECT_EQ(f.steps(), 1u);
    c.offset -= 3'000'000'000;  // then back past the start
    f.poll(200'000'000);
    EXPECT_EQ(f.step().load(), -500'000'000);
    EXPECT_EQ(f.steps(), 2u);
}

TEST(ClockStepFollower, ChangesWithinTheThresholdAreNotSteps) {
    FakeClock c;
    ClockStepFollower f(c.source(), kCfg);
    for (int i = 1; i <= 10; ++i) {
        c.offset += (i % 2 ? 90'000 : -90'000);  // read noise, never a step
        f.poll(std::int64_t{i} * 100'000'000);
    }
    EXPECT_EQ(f.steps(), 0u);
    EXPECT_EQ(f.step().load(), 0);
    c.offset += 150'000;  // a small step is still one
    f.poll(2'000'000'000);
    EXPECT_EQ(f.steps(), 1u);
    EXPECT_EQ(f.step().load(), 150'000);
}

TEST(ClockStepFollower, OneReadPerPeriodFromManyThreads) {
    FakeClock c;
    ClockStepFollower f(c.source(), kCfg);
    const int base_reads = c.reads.load();  // the constructor's
    std::atomic<std::int64_t> now{0};
    std::vector<std::thread> t;
    for (int k = 0; k < 4; ++k)
        t.emplace_back([&] {
            for (int i = 0; i < 100'000; ++i) f.poll(now.load());
        });
    for (int p = 1; p <= 5; ++p) {
        std::this_thread::yield();
        now.store(std::int64_t{p} * 100'000'000);
    }
    for (auto& x : t) x.join();
    for (int p = 6; p <= 7; ++p) f.poll(std::int64_t{p} * 100'000'000);
    // Periods 0..7 at most once each.
    EXPECT_LE(c.reads.load() - base_reads, 8);
    EXPECT_GE(c.reads.load() - base_reads, 3);
}

}  // namespace
