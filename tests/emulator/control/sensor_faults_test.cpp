// SPDX-License-Identifier: Apache-2.0
#include "mirage/control/sensor_faults.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

namespace mirage::control {
namespace {

TEST(SensorFaults, CellRoundTripsEveryField) {
    FaultCell c;
    EXPECT_EQ(c.load(), FaultSettings{});
    FaultSettings f{10000, 1000, -32768, 10000, true, false, true};
    c.store(f);
    EXPECT_EQ(c.load(), f);
    const FaultSettings g{1, 1, 32767, 1, false, true, false};
    c.store(g);
    EXPECT_EQ(c.load(), g);
    c.store(FaultSettings{65535, 65535, 0, 65535, false, false, false});  // clamped, not wrapped
    EXPECT_EQ(c.load(), (FaultSettings{10000, 1000, 0, 10000, false, false, false}));
}

// A reader on another thread sees one whole setting or the other, never fields of both.
TEST(SensorFaults, CellNeverTearsBetweenTwoSettings) {
    FaultCell c;
    const FaultSettings a{10000, 1000, -32768, 10000, true, true, true};
    const FaultSettings b{};
    c.store(a);
    // The writer starts once the reader reads, and the reader reads at least once: on a busy
    // machine the writer could otherwise finish before the reader's first load.
    std::atomic<bool> reading{false}, done{false};
    std::thread writer([&] {
        while (!reading.load()) std::this_thread::yield();
        for (int i = 0; i < 200000; ++i) c.store(i % 2 ? a : b);
        done = true;
    });
    std::uint64_t loads = 0, torn = 0;
    do {
        const FaultSettings f = c.load();
        torn += !(f == a || f == b);
        ++loads;
        reading = true;
    } while (!done.load());
    writer.join();
    EXPECT_GT(loads, 0u);
    EXPECT_EQ(torn, 0u);
}

// Bursts start with chance p at a packet outside a burst and last b packets: the long-run
// dropped share is p·b / (1 + p·(b − 1)) (a renewal process).
TEST(SensorFaults, DropperMatchesTheBurstRenewalShareAndRepeats) {
    FaultSettings f;
    f.drop_rate = 100;  // 1 %
    f.drop_burst = 5;
    PacketDropper a(42, 0), b(42, 0), other(42, 1);
    std::uint64_t same = 0, differ = 0, longest = 0, run = 0;
    constexpr int kN = 400000;
    for (int i = 0; i < kN; ++i) {
        const bool da = a.drop(f), db = b.drop(f), dc = other.drop(f);
        same += da == db;
        differ += da != dc;
        run = da ? run + 1 : 0;
        longest = std::max(longest, run);
    }
    const double p = 0.01, n = 5, want = p * n / (1 + p * (n - 1));
    EXPECT_NEAR(double(a.dropped()) / kN, want, 0.004);
    EXPECT_EQ(same, std::uint64_t(kN));  // counter-based: the same key repeats exactly
    EXPECT_GT(differ, 1000u);            // another sensor draws its own
    EXPECT_GE(longest, 5u);              // whole bursts
    f.drop_rate = 0;
    PacketDropper none(42, 0);
    for (int i = 0; i < 1000; ++i) EXPECT_FALSE(none.drop(f));
}

struct Recorder : wire::Packetizer {
    std::vector<core::PointRecord> got;
    std::uint64_t advanced = 0;
    void add(std::span<const core::PointRecord> p) override {
        got.insert(got.end(), p.begin(), p.end());
    }
    void advance_to(std::uint64_t n) override { advanced = n; }
    void emit_side_packets_until(core::GpsTime t) override { side_until = t; }
    void finish() override {}
    core::GpsTime side_until{};
};

std::vector<core::PointRecord> points(std::size_t n) {
    std::vector<core::PointRecord> v(n);
    for (std::size_t i = 0; i < n; ++i) {
        v[i].pulse = i;
        v[i].range_m = 20.0f;
    }
    return v;
}

TEST(SensorFaults, RangeBiasAndNoiseHaveTheirStatistics) {
    Recorder r;
    FaultCell c;
    FaultPacketizer fp(r, c, 7, 0);
    const auto pts = points(20000);
    fp.add(pts);
    EXPECT_EQ(r.got.size(), pts.size());
    EXPECT_EQ(r.got[0].range_m, 20.0f);  // no fault: untouched
    FaultSettings f;
    f.range_bias_mm = -250;
    f.range_noise_mm = 30;
    c.store(f);
    r.got.clear();
    fp.add(pts);
    double sum = 0, sq = 0;
    for (const auto& p : r.got) {
        const double d = p.range_m - 20.0;
        sum += d;
        sq += d * d;
    }
    const double mean = sum / double(r.got.size());
    const double sd = std::sqrt(sq / double(r.got.size()) - mean * mean);
    EXPECT_NEAR(mean, -0.250, 0.001);
    EXPECT_NEAR(sd, 0.030, 0.0015);
}

// Early side packets (docs/live-navigation.md §1) reach the packetizer behind the faults.
TEST(SensorFaults, SidePacketRequestsPassThrough) {
    Recorder r;
    FaultCell c;
    FaultPacketizer fp(r, c, 7, 0);
    const core::GpsTime t{std::chrono::seconds(123)};
    fp.emit_side_packets_until(t);
    EXPECT_EQ(r.side_until, t);
}

TEST(SensorFaults, StaleNavigationSendsEmptySlots) {
    Recorder r;
    FaultCell c;
    FaultSettings f;
    f.stale_nav = true;
    c.store(f);
    FaultPacketizer fp(r, c, 7, 0);
    fp.add(points(100));
    fp.advance_to(100);
    EXPECT_TRUE(r.got.empty());
    EXPECT_EQ(r.advanced, 100u);  // the slots still go out
    EXPECT_EQ(fp.stale_points(), 100u);
    fp.add(points(10));
    EXPECT_EQ(fp.stale_periods(), 1u);  // one period however many batches
    c.store(FaultSettings{});
    fp.add(points(10));
    EXPECT_EQ(r.got.size(), 10u);
    EXPECT_EQ(fp.points(), 10u);
}

}  // namespace
}  // namespace mirage::control
