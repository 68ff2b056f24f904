// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include "mirage/hostclock/host_clock.hpp"
#include "mirage/udp/lateness_histogram.hpp"
#include "mirage/udp/pacer.hpp"

namespace {

using mirage::core::GpsTime;
using mirage::core::Nanos;
using mirage::udp::LatenessHistogram;
using mirage::udp::Pacer;
using mirage::udp::PacerConfig;

TEST(LatenessHistogram, gives_nearest_rank_percentiles_at_1_us_resolution) {
    LatenessHistogram h(Nanos{50'000});
    for (int us = 1; us <= 100; ++us) h.add(Nanos{us * 1000 - 500});  // 0.5, 1.5, ... 99.5 µs
    EXPECT_EQ(h.count(), 100u);
    EXPECT_EQ(h.percentile(0.5), Nanos{50'000});  // 50th sample 49.5 µs -> bin [49, 50) µs
    EXPECT_EQ(h.percentile(0.99), Nanos{99'000});
    EXPECT_EQ(h.percentile(1.0), Nanos{99'500});  // capped by the exact worst
    EXPECT_EQ(h.worst(), Nanos{99'500});
    EXPECT_EQ(h.best(), Nanos{500});
    EXPECT_EQ(h.late(), 50u);  // 50.5 .. 99.5 µs exceed 50 µs
}

TEST(LatenessHistogram, keeps_early_and_overflow_samples_exactly_at_the_ends) {
    LatenessHistogram h;
    h.add(Nanos{-3'000});
    h.add(Nanos{20'000'000});  // 20 ms: beyond the last bin
    EXPECT_EQ(h.best(), Nanos{-3'000});
    EXPECT_EQ(h.worst(), Nanos{20'000'000});
    EXPECT_EQ(h.percentile(0.5), Nanos{1'000});  // early sample sits in bin 0
    EXPECT_EQ(h.percentile(1.0), Nanos{20'000'000});
    h.clear();
    EXPECT_EQ(h.count(), 0u);
    EXPECT_EQ(h.percentile(0.5), Nanos{0});
}

TEST(LatenessHistogram, counts_the_samples_from_a_lateness_on) {
    LatenessHistogram h;
    for (int us = 1; us <= 100; ++us) h.add(Nanos{us * 1000 - 500});  // 0.5 ... 99.5 µs
    h.add(Nanos{20'000'000});                                         // beyond the last bin
    EXPECT_EQ(h.count_from(Nanos{50'000}), 51u);  // 50.5 ... 99.5 µs and the 20 ms sample
    EXPECT_EQ(h.count_from(Nanos{50'999}), 51u);  // rounded down to the 50 µs bin
    EXPECT_EQ(h.count_from(Nanos{51'000}), 50u);
    EXPECT_EQ(h.count_from(Nanos{-1'000}), 101u);
    EXPECT_EQ(h.count_from(Nanos{30'000'000}), 1u);  // the overflow bin is kept whatever t
}

TEST(Pacer, maps_sensor_time_to_absolute_host_deadlines) {
    Pacer p;
    const GpsTime t0{Nanos{1'000'000'000'000}};
    p.anchor(t0, 5'000'000'000);
    EXPECT_EQ(p.deadline_ns(t0), 5'000'000'000);
    EXPECT_EQ(p.deadline_ns(t0 + Nanos{1'500'000'001}), 6'500'000'001);
    // Deadlines come from the anchor, never from the previous wake-up: 10^6 steps of 100 µs end
    // exactly 100 s later.
    EXPECT_EQ(p.deadline_ns(t0 + Nanos{1'000'000} * 100'000), 105'000'000'000);
}

TEST(Pacer, reports_lateness_of_a_deadline_already_past) {
    Pacer p;
    const GpsTime t0{};
    p.anchor(t0, mirage::hostclock::monotonic_ns() - 1'000'000'000);  // the schedule began 1 s ago
    const Nanos late = p.wait(t0);
    EXPECT_GE(late, Nanos{1'000'000'000});
    EXPECT_EQ(p.stats().count(), 1u);
    EXPECT_EQ(p.stats().late(), 1u);
}

TEST(Pacer, waits_until_the_deadline_and_never_before) {
    Pacer p;
    const GpsTime t0{};
    p.anchor(t0, mirage::hostclock::monotonic_ns());
    for (int k = 1; k <= 20; ++k) {
        const GpsTime t = t0 + Nanos{k * 200'000};  // 200 µs apart, 4 ms in all
        p.wait(t);
        EXPECT_GE(mirage::hostclock::monotonic_ns(), p.deadline_ns(t));
    }
    EXPECT_GE(p.stats().best(), Nanos{0});
}

TEST(Pacer, as_fast_as_possible_never_waits) {
    Pacer p(PacerConfig{true});
    const GpsTime t0{};
    // 1000 packets one second apart would take 17 minutes if paced.
    for (int k = 0; k < 1000; ++k) EXPECT_EQ(p.wait(t0 + std::chrono::seconds(k)), Nanos{0});
    EXPECT_EQ(p.stats().count(), 1000u);
    EXPECT_EQ(p.stats().worst(), Nanos{0});
}

}  // namespace
