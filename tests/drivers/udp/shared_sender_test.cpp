// SPDX-License-Identifier: Apache-2.0
// SharedSender over loopback: two streams of different rates through one sending thread, deadline
// order, backpressure (horizon and full queue), late packets, and the wake-up of a sleeping
// sender by an earlier packet (futex and condition variable; figures printed, not asserted).
#include "mirage/udp/shared_sender.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "mirage/udp/pacer.hpp"
#include "mirage/udp/udp_receiver.hpp"
#include "mirage/udp/udp_sender.hpp"

namespace {

using mirage::core::Nanos;
using mirage::udp::LatenessHistogram;
using mirage::udp::Pacer;
using mirage::udp::ReceivedDatagram;
using mirage::udp::SenderConfig;
using mirage::udp::SharedSender;
using mirage::udp::SharedSenderConfig;
using mirage::udp::StreamPorts;
using mirage::udp::UdpReceiver;
using mirage::udp::UdpSender;
using mirage::udp::WakeMethod;
using mirage::wire::Stream;
using Bytes = std::vector<std::uint8_t>;

constexpr Nanos kTimeout{2'000'000'000};  // generous: the machine is shared

SenderConfig to(std::uint16_t port) {
    SenderConfig c;
    c.host = "127.0.0.1";
    c.ports = StreamPorts{port, 0, 0};
    return c;
}

// Packet k of stream `tag`: tag, k, then a pattern; sizes vary so slots hold different lengths.
Bytes packet(std::uint32_t tag, std::uint32_t k) {
    Bytes b(16 + (k * 131) % 1400);
    for (std::size_t i = 0; i < b.size(); ++i) b[i] = static_cast<std::uint8_t>(i * 13 + k + tag);
    std::memcpy(b.data(), &tag, 4);
    std::memcpy(b.data() + 4, &k, 4);
    return b;
}

struct Arrival {
    std::uint32_t k = 0;
    std::int64_t kernel_ns = 0;
    bool intact = false;
};

// Receives `n` packets of stream `tag` (or stops after a timeout).
std::vector<Arrival> receive_n(UdpReceiver& rx, std::uint32_t tag, std::size_t n) {
    std::vector<Arrival> got;
    ReceivedDatagram d;
    while (got.size() < n && rx.receive(d, kTimeout)) {
        Arrival a;
        std::uint32_t t = 0;
        if (d.payload.size() >= 8) {
            std::memcpy(&t, d.payload.data(), 4);
            std::memcpy(&a.k, d.payload.data() + 4, 4);
        }
        a.kernel_ns = d.kernel_time_ns;
        a.intact = t == tag && d.payload == packet(tag, a.k);
        got.push_back(a);
    }
    return got;
}

class SharedSenderTwoStreams : public ::testing::TestWithParam<WakeMethod> {};

TEST_P(SharedSenderTwoStreams, delivers_both_rates_complete_in_order_and_never_early) {
    // Stream A: 300 packets at 4 kHz; stream B: 60 packets at 800 Hz (75 ms each), each from its
    // own producer thread, as two render writers would.
    constexpr std::uint32_t kA = 300, kB = 60;
    constexpr std::int64_t kPeriodA = 250'000, kPeriodB = 1'250'000;
    UdpReceiver rx_a, rx_b;
    UdpSender tx_a(to(rx_a.port())), tx_b(to(rx_b.port()));
    SharedSenderConfig cfg;
    cfg.wake = GetParam();
    SharedSender ss(cfg);
    const auto ca = ss.open(tx_a);
    const auto cb = ss.open(tx_b);
    EXPECT_NE(ca, cb);
    const std::int64_t offset = mirage::hostclock::realtime_minus_monotonic();
    const std::int64_t t0 = mirage::hostclock::monotonic_ns() + 5'000'000;

    std::vector<Arrival> got_a, got_b;
    std::thread recv_a([&] { got_a = receive_n(rx_a, 1, kA); });
    std::thread recv_b([&] { got_b = receive_n(rx_b, 2, kB); });
    std::thread prod_a([&] {
        for (std::uint32_t k = 0; k < kA; ++k)
            EXPECT_TRUE(ss.submit(ca, Stream::Data, t0 + k * kPeriodA, packet(1, k)));
    });
    std::thread prod_b([&] {
        for (std::uint32_t k = 0; k < kB; ++k)
            EXPECT_TRUE(ss.submit(cb, Stream::Data, t0 + k * kPeriodB, packet(2, k)));
    });
    prod_a.join();
    prod_b.join();
    ss.flush(ca);
    ss.flush(cb);
    recv_a.join();
    recv_b.join();

    // All there, intact, in deadline order, and never before their deadline (the thread spins
    // to it): kernel receive time − deadline ≥ 0 for every packet.
    const auto check = [&](const std::vector<Arrival>& got, std::uint32_t n, std::int64_t period,
                           const char* name) {
        ASSERT_EQ(got.size(), n) << name;
        for (std::uint32_t i = 0; i < n; ++i) {
            EXPECT_EQ(got[i].k, i) << name;
            EXPECT_TRUE(got[i].intact) << name << " " << i;
            if (got[i].kernel_ns != 0) {
                EXPECT_GE(got[i].kernel_ns - offset - (t0 + i * period), -10'000)
                    << name << " " << i;  // the realtime/monotonic offset read error
            }
        }
    };
    check(got_a, kA, kPeriodA, "A");
    check(got_b, kB, kPeriodB, "B");

    for (const auto& [id, n] : {std::pair{ca, kA}, std::pair{cb, kB}}) {
        const auto c = ss.counters(id);
        EXPECT_EQ(c.submitted, n);
        EXPECT_EQ(c.sent, n);
        EXPECT_EQ(c.failed, 0u);
        const auto h = ss.lateness(id);
        EXPECT_EQ(h.count(), n);         // one lateness sample per packet
        EXPECT_GE(h.best().count(), 0);  // spins to the deadline: never early
        EXPECT_EQ(h.late(), c.late);
        EXPECT_EQ(h.worst(), c.worst);
        std::printf("%s stream %u: lateness p50 %.1f µs p99 %.1f µs worst %.1f µs\n",
                    GetParam() == WakeMethod::Futex ? "futex" : "condvar", id,
                    double(h.percentile(0.5).count()) / 1e3,
                    double(h.percentile(0.99).count()) / 1e3, double(h.worst().count()) / 1e3);
    }
}

INSTANTIATE_TEST_SUITE_P(Wake, SharedSenderTwoStreams,
                         ::testing::Values(WakeMethod::Futex, WakeMethod::CondVar),
                         [](const auto& info) {
                             return std::string(info.param == WakeMethod::Futex ? "futex"
                                                                                : "condvar");
                         });

TEST(SharedSender, sends_packets_of_two_channels_in_global_deadline_order) {
    // Everything is queued well before the first deadline, in scrambled order: one thread sends
    // in deadline order across channels (equal deadlines in submission order), so the receiver,
    // shared by both channels, sees them sorted.
    UdpReceiver rx;
    UdpSender tx_a(to(rx.port())), tx_b(to(rx.port()));
    SharedSenderConfig cfg;
    cfg.horizon = Nanos{5'000'000'000};
    SharedSender ss(cfg);
    const auto ca = ss.open(tx_a);
    const auto cb = ss.open(tx_b);
    const std::int64_t t0 = mirage::hostclock::monotonic_ns() + 300'000'000;
    // A: k = 0..39 at 100 µs steps, B: k = 0..19 at 230 µs steps (B's k = 10 ties A's 23),
    // submitted B last-first, then A first-last.
    std::vector<std::pair<std::int64_t, std::uint32_t>> expected;  // (deadline, tag << 16 | k)
    for (std::uint32_t k = 20; k-- > 0;) {
        ASSERT_TRUE(ss.submit(cb, Stream::Data, t0 + k * 230'000, packet(2, k)));
        expected.emplace_back(t0 + k * 230'000, 2u << 16 | k);
    }
    for (std::uint32_t k = 0; k < 40; ++k) {
        ASSERT_TRUE(ss.submit(ca, Stream::Data, t0 + k * 100'000, packet(1, k)));
        expected.emplace_back(t0 + k * 100'000, 1u << 16 | k);
    }
    // The tie (t0 + 2.3 ms) goes B first: it was submitted first.
    std::stable_sort(expected.begin(), expected.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    ASSERT_LT(mirage::hostclock::monotonic_ns(), t0)
        << "queued after the first deadline: order not tested";
    ss.flush(ca);
    ss.flush(cb);
    ReceivedDatagram d;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        ASSERT_TRUE(rx.receive(d, kTimeout)) << i;
        std::uint32_t tag = 0, k = 0;
        std::memcpy(&tag, d.payload.data(), 4);
        std::memcpy(&k, d.payload.data() + 4, 4);
        EXPECT_EQ(tag << 16 | k, expected[i].second) << "position " << i;
    }
    EXPECT_EQ(ss.counters(ca).sent, 40u);
    EXPECT_EQ(ss.counters(cb).sent, 20u);
    // Every send call is timed, per channel; a loopback send takes well under a second.
    EXPECT_EQ(ss.send_durations(ca).count(), 40u);
    EXPECT_EQ(ss.send_durations(cb).count(), 20u);
    EXPECT_LT(ss.send_durations(ca).worst().count(), 1'000'000'000);
    // The thread slept toward t0 − margin at least once (300 ms away), so a timed wake-up was
    // measured, and it ended after the instant asked for but not seconds after.
    const LatenessHistogram w = ss.wake_lateness();
    EXPECT_GE(w.count(), 1u);
    EXPECT_LT(w.worst().count(), 1'000'000'000);
}

TEST(SharedSender, submit_beyond_the_horizon_blocks_until_within_it) {
    UdpReceiver rx;
    UdpSender tx(to(rx.port()));
    SharedSenderConfig cfg;
    cfg.horizon = Nanos{20'000'000};
    SharedSender ss(cfg);
    const auto ch = ss.open(tx);
    // Within the horizon: no wait.
    const std::int64_t s0 = mirage::hostclock::monotonic_ns();
    ASSERT_TRUE(ss.submit(ch, Stream::Data, s0 + 5'000'000, packet(1, 0)));
    EXPECT_EQ(ss.horizon_waits(), 0u);
    // 120 ms ahead with a 20 ms horizon: submit cannot return before deadline − horizon.
    const std::int64_t deadline = mirage::hostclock::monotonic_ns() + 120'000'000;
    ASSERT_TRUE(ss.submit(ch, Stream::Data, deadline, packet(1, 1)));
    const std::int64_t back = mirage::hostclock::monotonic_ns();
    EXPECT_EQ(ss.horizon_waits(), 1u);
    EXPECT_GE(back, deadline - 20'000'000);
    EXPECT_LT(back - (deadline - 20'000'000), 2'000'000'000);  // no runaway wait
    ss.flush(ch);
    EXPECT_EQ(ss.counters(ch).sent, 2u);
    EXPECT_EQ(ss.full_waits(), 0u);
}

TEST(SharedSender, full_queue_blocks_submit_until_a_packet_is_sent) {
    UdpReceiver rx;
    UdpSender tx(to(rx.port()));
    SharedSenderConfig cfg;
    cfg.capacity = 4;
    cfg.horizon = Nanos{5'000'000'000};
    SharedSender ss(cfg);
    const auto ch = ss.open(tx);
    const std::int64_t t0 = mirage::hostclock::monotonic_ns() + 50'000'000;
    for (std::uint32_t k = 0; k < 4; ++k)
        ASSERT_TRUE(ss.submit(ch, Stream::Data, t0 + k * 1'000'000, packet(1, k)));
    EXPECT_EQ(ss.full_waits(), 0u);
    // The fifth needs a slot: the first frees only once sent, at or after its deadline t0.
    ASSERT_TRUE(ss.submit(ch, Stream::Data, t0 + 4'000'000, packet(1, 4)));
    EXPECT_GE(mirage::hostclock::monotonic_ns(), t0);
    EXPECT_EQ(ss.full_waits(), 1u);
    ss.flush(ch);
    EXPECT_EQ(ss.counters(ch).sent, 5u);
    ReceivedDatagram d;
    for (std::uint32_t k = 0; k < 5; ++k) {
        ASSERT_TRUE(rx.receive(d, kTimeout));
        EXPECT_EQ(d.payload, packet(1, k));
    }
}

TEST(SharedSender, packet_past_its_deadline_goes_out_at_once_and_counts_late) {
    UdpReceiver rx;
    UdpSender tx(to(rx.port()));
    SharedSender ss;  // late threshold 100 µs
    const auto ch = ss.open(tx);
    const std::int64_t deadline = mirage::hostclock::monotonic_ns() - 10'000'000;  // 10 ms ago
    ASSERT_TRUE(ss.submit(ch, Stream::Data, deadline, packet(1, 7)));
    ss.flush(ch);
    const auto h = ss.lateness(ch);
    ASSERT_EQ(h.count(), 1u);
    EXPECT_GE(h.worst().count(), 10'000'000);
    EXPECT_EQ(h.late(), 1u);
    EXPECT_EQ(ss.counters(ch).late, 1u);
    ReceivedDatagram d;
    ASSERT_TRUE(rx.receive(d, kTimeout));
    EXPECT_EQ(d.payload, packet(1, 7));
}

// A stopped sensor's queue is dropped unsent; another channel's packets, interleaved in the
// same heap, all go out in order, and a flush of the emptied channel returns at once.
TEST(SharedSender, discard_drops_one_channels_queue_and_keeps_the_others) {
    UdpReceiver rx_a, rx_b;
    UdpSender tx_a(to(rx_a.port())), tx_b(to(rx_b.port()));
    SharedSenderConfig cfg;
    cfg.horizon = Nanos{5'000'000'000};
    SharedSender ss(cfg);
    const auto ca = ss.open(tx_a);
    const auto cb = ss.open(tx_b);
    const std::int64_t t0 = mirage::hostclock::monotonic_ns() + 200'000'000;
    for (std::uint32_t k = 0; k < 30; ++k) {
        ASSERT_TRUE(ss.submit(ca, Stream::Data, t0 + k * 1'000'000, packet(1, k)));
        ASSERT_TRUE(ss.submit(cb, Stream::Data, t0 + k * 1'000'000 + 500'000, packet(2, k)));
    }
    EXPECT_EQ(ss.discard(ca), 30u);
    EXPECT_EQ(ss.discard(ca), 0u);
    const std::int64_t f0 = mirage::hostclock::monotonic_ns();
    ss.flush(ca);
    EXPECT_LT(mirage::hostclock::monotonic_ns() - f0, 100'000'000);  // nothing left to wait for
    ss.flush(cb);
    EXPECT_EQ(ss.counters(ca).sent, 0u);
    EXPECT_EQ(ss.counters(ca).discarded, 30u);
    EXPECT_EQ(ss.counters(cb).sent, 30u);
    ReceivedDatagram d;
    for (std::uint32_t k = 0; k < 30; ++k) {
        ASSERT_TRUE(rx_b.receive(d, kTimeout)) << k;
        EXPECT_EQ(d.payload, packet(2, k));
    }
    EXPECT_FALSE(rx_a.receive(d, std::chrono::milliseconds(50)));
    // The freed slots serve new packets.
    ASSERT_TRUE(ss.submit(ca, Stream::Data, mirage::hostclock::monotonic_ns(), packet(1, 99)));
    ss.flush(ca);
    EXPECT_EQ(ss.counters(ca).sent, 1u);
}

TEST(SharedSender, unknown_or_closed_channel_is_refused_without_throwing) {
    UdpReceiver rx;
    UdpSender tx(to(rx.port()));
    SharedSender ss;
    const auto ch = ss.open(tx);
    EXPECT_FALSE(ss.submit(ch + 1, Stream::Data, mirage::hostclock::monotonic_ns(), packet(1, 0)));
    ss.close(ch);
    EXPECT_FALSE(ss.submit(ch, Stream::Data, mirage::hostclock::monotonic_ns(), packet(1, 0)));
    EXPECT_EQ(ss.counters(ch).submitted, 0u);
    SharedSenderConfig zero;
    zero.capacity = 0;
    EXPECT_THROW(SharedSender{zero}, mirage::ConfigError);
}

// A sender asleep toward a far deadline must wake for a packet due now. Each sample queues a
// far packet (15 ms ahead), then an urgent one due at once, and waits for the urgent one to
// arrive; the urgent channel's lateness is the wake-up latency. Figures are printed.
TEST(SharedSender, earlier_packet_wakes_the_sleeping_sender) {
    for (const WakeMethod m : {WakeMethod::Futex, WakeMethod::CondVar}) {
        UdpReceiver rx_far, rx_now;
        UdpSender tx_far(to(rx_far.port())), tx_now(to(rx_now.port()));
        SharedSenderConfig cfg;
        cfg.wake = m;
        SharedSender ss(cfg);
        const auto far = ss.open(tx_far);
        const auto now = ss.open(tx_now);
        constexpr std::uint32_t kSamples = 200;
        ReceivedDatagram d;
        std::uint32_t received = 0;
        for (std::uint32_t k = 0; k < kSamples; ++k) {
            ASSERT_TRUE(ss.submit(far, Stream::Data, mirage::hostclock::monotonic_ns() + 15'000'000,
                                  packet(1, k)));
            ASSERT_TRUE(
                ss.submit(now, Stream::Data, mirage::hostclock::monotonic_ns(), packet(2, k)));
            if (rx_now.receive(d, kTimeout)) ++received;
            rx_far.drain();
        }
        ss.flush(far);
        EXPECT_EQ(received, kSamples);
        const auto h = ss.lateness(now);
        EXPECT_EQ(h.count(), kSamples);
        EXPECT_EQ(ss.counters(far).sent, kSamples);
        EXPECT_GE(ss.wakeups(), 1u);  // the urgent packets needed the thread before its plan
        std::printf(
            "wake-up (%s): %llu wake-ups, urgent lateness p50 %.1f µs, p99 %.1f µs, "
            "worst %.1f µs\n",
            m == WakeMethod::Futex ? "futex" : "condvar",
            static_cast<unsigned long long>(ss.wakeups()), double(h.percentile(0.5).count()) / 1e3,
            double(h.percentile(0.99).count()) / 1e3, double(h.worst().count()) / 1e3);
    }
}

}  // namespace
