// SPDX-License-Identifier: Apache-2.0
// Every shared capture replayed at 1x over loopback to port-0 receivers through --port-map:
// every payload arrives byte-identical and in order; the arrival timing against the capture's is
// printed. Record round trip: replay -> Recorder -> pcap whose payloads equal the capture's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <thread>

#include "mirage/pcap/pcap.hpp"
#include "mirage/replay/recorder.hpp"
#include "mirage/replay/replayer.hpp"
#include "mirage/udp/udp_receiver.hpp"
#include "test_paths.hpp"

namespace {

using namespace mirage;
using namespace std::chrono_literals;

struct Arrival {
    std::vector<std::uint8_t> payload;
    std::int64_t time_ns;
};

// Receives until `expected` datagrams arrived or 2 s passed without any.
std::vector<Arrival> collect(udp::UdpReceiver& rx, std::size_t expected) {
    std::vector<Arrival> v;
    udp::ReceivedDatagram d;
    while (v.size() < expected && rx.receive(d, core::Nanos{2'000'000'000}))
        v.push_back({d.payload, d.kernel_time_ns});
    return v;
}

void replay_capture_byte_identically(const std::string& name) {
    MIRAGE_CAPTURE_OR_SKIP(path, name);
    const auto original = pcap::read_udp(path.string());
    std::map<std::uint16_t, std::vector<const pcap::UdpDatagram*>> by_port;
    for (const auto& d : original) by_port[d.dst.port].push_back(&d);

    std::map<std::uint16_t, std::unique_ptr<udp::UdpReceiver>> rx;
    replay::ReplayConfig c;
    c.path = path.string();
    for (const auto& [port, v] : by_port) {
        rx[port] = std::make_unique<udp::UdpReceiver>(udp::ReceiverConfig{});
        c.port_map[port] = rx[port]->port();
    }
    std::map<std::uint16_t, std::vector<Arrival>> got;
    std::vector<std::thread> threads;
    for (auto& [port, r] : rx) got[port] = {};  // no map insertion from the threads
    for (auto& [port, r] : rx) {
        auto* recv = r.get();
        auto* out = &got[port];
        const auto n = by_port[port].size();
        threads.emplace_back([recv, out, n] { *out = collect(*recv, n); });
    }
    const auto s = replay::replay(c);
    for (auto& t : threads) t.join();
    std::cout << name << ": " << replay::format_summary(s);
    EXPECT_EQ(s.packets, original.size());
    EXPECT_TRUE(s.error.empty()) << s.error;

    // Timing: (arrival − capture time) minus its least value over the run.
    std::vector<std::int64_t> offsets;
    for (const auto& [port, v] : by_port) {
        const auto& a = got[port];
        ASSERT_EQ(a.size(), v.size()) << name << " port " << port;
        for (std::size_t i = 0; i < v.size(); ++i) {
            ASSERT_EQ(a[i].payload, v[i]->payload) << name << " port " << port << " #" << i;
            offsets.push_back(a[i].time_ns - v[i]->time_ns);
        }
    }
    const auto least = *std::min_element(offsets.begin(), offsets.end());
    for (auto& o : offsets) o -= least;
    std::sort(offsets.begin(), offsets.end());
    auto q = [&](double p) {
        const auto i = static_cast<std::size_t>(p * static_cast<double>(offsets.size() - 1));
        return static_cast<double>(offsets[i]) * 1e-3;
    };
    std::printf("%s: %zu payloads identical; arrival timing error vs capture (kernel receive "
                "stamps): p50 %.1f us, p99 %.1f us, max %.1f us\n",
                name.c_str(), offsets.size(), q(0.5), q(0.99), q(1.0));
}

TEST(ReplayLoopback, vlp16_capture_replays_byte_identically) {
    replay_capture_byte_identically("vlp16_example.pcap");
}
TEST(ReplayLoopback, hdl32e_capture_with_position_packets_replays_byte_identically) {
    replay_capture_byte_identically("hdl32e_with_position.pcap");
}
TEST(ReplayLoopback, ouster_legacy_capture_with_ip_fragments_replays_byte_identically) {
    replay_capture_byte_identically("os1_64_legacy.pcap");
}
TEST(ReplayLoopback, ouster_rng19_capture_replays_byte_identically) {
    replay_capture_byte_identically("os2_128_rng19.pcap");
}

TEST(ReplayLoopback, top_speed_sends_every_packet_in_batches) {
    MIRAGE_CAPTURE_OR_SKIP(path, "hdl32e_with_position.pcap");
    // A bound socket nobody reads: the kernel queues what fits and drops the rest, so this
    // measures the sender alone.
    udp::UdpReceiver sink(udp::ReceiverConfig{});
    replay::ReplayConfig c;
    c.path = path.string();
    c.port_map = {{2368, sink.port()}, {8308, sink.port()}};
    c.speed = 0;
    c.loops = 100;  // 97,600 packets
    const auto s = replay::replay(c);
    std::cout << replay::format_summary(s);
    EXPECT_EQ(s.packets, 97'600u);
    EXPECT_EQ(s.failed, 0u);
    EXPECT_LT(s.syscalls, s.packets / 50);  // batched: about 128 per sendmmsg
}

TEST(ReplayLoopback, impaired_replay_delivers_exactly_what_the_summary_says) {
    MIRAGE_CAPTURE_OR_SKIP(path, "vlp16_example.pcap");
    udp::UdpReceiver rx(udp::ReceiverConfig{});
    replay::ReplayConfig c;
    c.path = path.string();
    c.port_map = {{2368, rx.port()}};
    c.speed = 4;
    c.impair.drop = 0.1;
    c.impair.drop_burst = 2;
    c.impair.duplicate = 0.1;
    c.impair.reorder = 0.1;
    c.impair.seed = 11;
    std::vector<Arrival> got;
    std::thread t([&] { got = collect(rx, 1000); });
    const auto s = replay::replay(c);
    t.join();
    std::cout << replay::format_summary(s);
    EXPECT_EQ(s.impair.in, 84u);
    EXPECT_EQ(got.size(), s.packets);
    EXPECT_EQ(s.packets, 84 - s.impair.dropped + s.impair.duplicated);
    EXPECT_GT(s.impair.dropped, 0u);
}

TEST(RecordLoopback, replay_then_record_round_trips_every_payload_and_address) {
    MIRAGE_CAPTURE_OR_SKIP(path, "hdl32e_with_position.pcap");
    test::TempDir dir;
    replay::RecordConfig rc;
    rc.ports = {0, 0};
    rc.bind_host = "127.0.0.1";
    rc.out = dir.file("rec.pcap");
    replay::Recorder rec(rc);
    ASSERT_EQ(rec.ports().size(), 2u);
    std::atomic<bool> stop{false};
    replay::RecordResult result;
    std::thread t([&] { result = rec.run(stop); });
    replay::ReplayConfig c;
    c.path = path.string();
    c.port_map = {{2368, rec.ports()[0]}, {8308, rec.ports()[1]}};
    const auto s = replay::replay(c);
    const auto original = pcap::read_udp(path.string());
    ASSERT_EQ(s.packets, original.size());
    // Stop once everything arrived (bounded wait; the recorder polls every 50 ms).
    for (int i = 0; i < 200; ++i) {
        std::this_thread::sleep_for(10ms);
        if (std::filesystem::exists(rc.out) && i > 20) break;
    }
    stop = true;
    t.join();
    ASSERT_TRUE(result.error.empty()) << result.error;
    EXPECT_EQ(result.written, original.size());
    pcap::Reader r(rc.out);
    std::map<std::uint16_t, std::vector<pcap::UdpDatagram>> got;
    pcap::UdpDatagram d;
    while (r.next(d)) got[d.dst.port].push_back(d);
    EXPECT_TRUE(r.error().empty());
    std::size_t i0 = 0, i1 = 0;
    for (const auto& o : original) {
        const bool data = o.dst.port == 2368;
        auto& v = got[data ? rec.ports()[0] : rec.ports()[1]];
        auto& i = data ? i0 : i1;
        ASSERT_LT(i, v.size());
        EXPECT_EQ(v[i].payload, o.payload) << i;
        EXPECT_EQ(v[i].src.ip, (std::array<std::uint8_t, 4>{127, 0, 0, 1}));
        EXPECT_EQ(v[i].dst.ip, (std::array<std::uint8_t, 4>{127, 0, 0, 1}));
        EXPECT_GT(v[i].time_ns, 1'600'000'000'000'000'000);  // a kernel wall-clock stamp
        ++i;
    }
    EXPECT_EQ(i0 + i1, original.size());
    std::printf("record: %llu datagrams, %llu bytes of pcap\n",
                static_cast<unsigned long long>(result.written),
                static_cast<unsigned long long>(result.file_bytes));
}

}  // namespace
