// SPDX-License-Identifier: Apache-2.0
// `mirage replay` at 1x keeps the capture's timing, checked from outside: a receiver stamps every
// datagram in the kernel, and each arrival is compared with its due time, anchor + (t_i − t_0),
// on the same clock. A replayer that ignored the timestamps (sent at once) or slept relative
// intervals (drift) fails here.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

#include "mirage/hostclock/host_clock.hpp"
#include "mirage/pcap/writer.hpp"
#include "mirage/replay/recorder.hpp"
#include "mirage/replay/replayer.hpp"
#include "mirage/replay/time_order.hpp"
#include "mirage/udp/udp_receiver.hpp"
#include "test_paths.hpp"

namespace mirage::replay {
namespace {

constexpr std::int64_t kSpanNs = 10'000'000'000;  // 10 s of capture
constexpr std::int64_t kPeriodNs = 1'327'000;     // a VLP-16's packet period, about
constexpr std::int64_t kStartNs = 1'700'000'000'000'000'000;

// A synthetic capture: one 1206-byte datagram every period, every 50th period a burst of three
// with one timestamp (as a sensor's position and data packets can be); payload = index.
std::vector<std::int64_t> write_capture(const std::string& path) {
    pcap::Writer w(path);
    std::vector<std::int64_t> times;
    std::vector<std::uint8_t> payload(1206);
    for (std::int64_t t = 0; t < kSpanNs; t += kPeriodNs) {
        const int copies = (t / kPeriodNs) % 50 == 0 ? 3 : 1;
        for (int c = 0; c < copies; ++c) {
            const auto i = static_cast<std::uint32_t>(times.size());
            std::copy_n(reinterpret_cast<const std::uint8_t*>(&i), 4, payload.begin());
            w.write(kStartNs + t, {{192, 168, 1, 201}, 2368}, {{192, 168, 1, 100}, 2368}, payload);
            times.push_back(t);
        }
    }
    w.close();
    return times;
}

double quantile(std::vector<std::int64_t> v, double q) {
    std::sort(v.begin(), v.end());
    return static_cast<double>(v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))]);
}

TEST(ReplayTiming, one_x_is_never_early_on_time_at_the_median_and_does_not_drift) {
    test::TempDir tmp;
    const std::string path = tmp.file("synthetic.pcap");
    const auto times = write_capture(path);

    udp::UdpReceiver rx(udp::ReceiverConfig{});
    ReplayConfig c;
    c.path = path;
    c.port_map = {{2368, rx.port()}};
    std::vector<std::int64_t> arrival(times.size(), 0);  // kernel stamps, CLOCK_REALTIME
    std::thread receiver([&] {
        udp::ReceivedDatagram d;
        std::size_t got = 0;
        while (got < times.size() && rx.receive(d, core::Nanos{2'000'000'000})) {
            std::uint32_t i = 0;
            std::copy_n(d.payload.begin(), 4, reinterpret_cast<std::uint8_t*>(&i));
            if (i < arrival.size()) arrival[i] = d.kernel_time_ns;
            ++got;
        }
    });
    const ReplaySummary s = replay(c);
    receiver.join();
    const std::int64_t rt_minus_mono = hostclock::realtime_minus_monotonic();
    ASSERT_EQ(s.packets, times.size());
    ASSERT_GE(s.anchor_ns, 0);

    // Error of each arrival against its due time, both on CLOCK_MONOTONIC.
    std::vector<std::int64_t> err, first_s, last_s;
    for (std::size_t i = 0; i < times.size(); ++i) {
        ASSERT_NE(arrival[i], 0) << "datagram " << i << " never arrived";
        const std::int64_t e = arrival[i] - rt_minus_mono - (s.anchor_ns + times[i]);
        err.push_back(e);
        if (times[i] < 1'000'000'000) first_s.push_back(e);
        if (times[i] >= kSpanNs - 1'000'000'000) last_s.push_back(e);
    }
    const double earliest = quantile(err, 0.0), median = quantile(err, 0.5);
    const double p99 = quantile(err, 0.99);
    const double drift = quantile(last_s, 0.5) - quantile(first_s, 0.5);
    std::printf(
        "replay 1x of %zu datagrams over 10 s: arrival - due time: earliest %.1f us, "
        "median %.1f us, p99 %.1f us; drift (median of the last second - first) %.1f us; "
        "the replayer's own send-call lateness p50 %.1f us, best %.1f us\n",
        err.size(), earliest * 1e-3, median * 1e-3, p99 * 1e-3, drift * 1e-3,
        static_cast<double>(s.lateness.percentile(0.5).count()) * 1e-3,
        static_cast<double>(s.lateness.best().count()) * 1e-3);
    // Never early: the kernel stamps after the send, which starts at or after the due time. The
    // slack is the uncertainty of mapping CLOCK_REALTIME stamps onto CLOCK_MONOTONIC (a bracket
    // of two clock reads, well under a microsecond), not a tolerance for early sends.
    EXPECT_GE(earliest, -2'000.0);
    EXPECT_GE(s.lateness.best().count(), 0);
    EXPECT_LT(median, 1'000'000.0);
    EXPECT_LT(std::abs(drift), 100'000.0);
}

// Top speed on captures of 1 and 75 datagrams (one sendmmsg each): the time is that of the send
// call, so the rate is a finite positive number, never "0 packets/s in 0 s".
TEST(ReplayTiming, top_speed_on_a_short_capture_reports_a_real_rate) {
    test::TempDir tmp;
    udp::UdpReceiver sink(udp::ReceiverConfig{});
    for (const int n : {1, 75}) {
        const std::string path = tmp.file("short" + std::to_string(n) + ".pcap");
        {
            pcap::Writer w(path);
            const std::vector<std::uint8_t> payload(1206, 0x5a);
            for (int i = 0; i < n; ++i)
                w.write(kStartNs + i * kPeriodNs, {{10, 0, 0, 1}, 7502}, {{10, 0, 0, 2}, 7502},
                        payload);
        }
        ReplayConfig c;
        c.path = path;
        c.port_map = {{7502, sink.port()}};
        c.speed = 0;
        const ReplaySummary s = replay(c);
        const std::string text = format_summary(s);
        std::printf("%s", text.c_str());
        EXPECT_EQ(s.packets, static_cast<std::uint64_t>(n));
        EXPECT_GT(s.elapsed_ns, 0) << n;
        EXPECT_EQ(text.find("top speed: 0 packets/s"), std::string::npos) << text;
        EXPECT_EQ(text.find("sent in 0.000000 s"), std::string::npos) << text;
        sink.drain();
    }
}

}  // namespace
}  // namespace mirage::replay

namespace mirage::replay {
namespace {

// Records from two sockets interleave in time; they leave oldest first once old enough, ties in
// arrival order, and one that comes after a later one already left is counted.
TEST(TimeOrder, releases_records_oldest_first_after_the_hold) {
    TimeOrder order(50);
    std::vector<std::int64_t> out;
    auto take = [&](const TimeOrder::Record& r) {
        out.push_back(r.time_ns * 10 + static_cast<std::int64_t>(r.payload.at(0)));
        return true;
    };
    order.add({100, {}, {}, {1}});  // socket A
    order.add({130, {}, {}, {1}});
    order.add({110, {}, {}, {2}});  // socket B, read after A's
    order.add({130, {}, {}, {2}});
    order.release(170, false, take);  // everything up to 120
    EXPECT_EQ(out, (std::vector<std::int64_t>{1001, 1102}));
    order.add({105, {}, {}, {3}});  // read too late: 110 already left
    order.release(0, true, take);
    EXPECT_EQ(out, (std::vector<std::int64_t>{1001, 1102, 1053, 1301, 1302}));
    EXPECT_EQ(order.out_of_order(), 1u);
}

// A capture of two ports recorded and replayed: the recording is in time order although the
// recorder reads one socket at a time, and replaying it sends every datagram (one stamped before
// the first used to be dropped as "outside --from").
TEST(RecordReplay, two_ports_record_in_time_order_and_replay_whole) {
    test::TempDir tmp;
    const std::string capture = tmp.file("two.pcap");
    {
        pcap::Writer w(capture);
        std::vector<std::uint8_t> payload(200);
        for (std::uint32_t i = 0; i < 400; ++i) {
            std::copy_n(reinterpret_cast<const std::uint8_t*>(&i), 4, payload.begin());
            const std::uint16_t port = i % 2 ? 8308 : 2368;  // both ports at the same instants
            w.write(kStartNs + (i / 2) * 1'000'000, {{10, 0, 0, 1}, port}, {{10, 0, 0, 2}, port},
                    payload);
        }
    }
    RecordConfig rc;
    rc.ports = {0, 0};
    rc.bind_host = "127.0.0.1";
    rc.out = tmp.file("rec.pcap");
    Recorder rec(rc);
    std::atomic<bool> stop{false};
    RecordResult result;
    std::thread t([&] { result = rec.run(stop); });
    ReplayConfig c;
    c.path = capture;
    c.speed = 0;  // bursts: the recorder finds many datagrams waiting on each socket
    c.port_map = {{2368, rec.ports()[0]}, {8308, rec.ports()[1]}};
    ASSERT_EQ(replay(c).packets, 400u);
    const std::int64_t deadline = hostclock::monotonic_ns() + 5'000'000'000;
    while (rec.received() < 400 && hostclock::monotonic_ns() < deadline)
        hostclock::sleep_until_monotonic(hostclock::monotonic_ns() + 5'000'000);
    stop = true;
    t.join();
    ASSERT_TRUE(result.error.empty()) << result.error;
    ASSERT_EQ(result.written, 400u);
    const auto recorded = pcap::read_udp(rc.out);
    ASSERT_EQ(recorded.size(), 400u);
    for (std::size_t i = 1; i < recorded.size(); ++i)
        EXPECT_GE(recorded[i].time_ns, recorded[i - 1].time_ns) << "record " << i;

    udp::UdpReceiver sink(udp::ReceiverConfig{});
    ReplayConfig again;
    again.path = rc.out;
    again.speed = 0;
    again.port_map = {{rec.ports()[0], sink.port()}, {rec.ports()[1], sink.port()}};
    const ReplaySummary s = replay(again);
    EXPECT_EQ(s.packets, 400u);
    EXPECT_EQ(s.out_of_range, 0u);
}

}  // namespace
}  // namespace mirage::replay
