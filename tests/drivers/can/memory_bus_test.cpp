// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "mirage/can/can_bus.hpp"
#include "mirage/can/memory_bus.hpp"

namespace mirage::can {
namespace {

using namespace std::chrono_literals;

nav::CanFrame frame(std::uint32_t id, std::uint8_t first, bool extended = false) {
    nav::CanFrame f;
    f.id = id;
    f.extended = extended;
    f.len = 3;
    f.data = {first, static_cast<std::uint8_t>(first + 1), static_cast<std::uint8_t>(first + 2)};
    return f;
}

TEST(MemoryBus, every_other_bus_of_the_name_receives_a_frame_but_not_the_sender) {
    auto a = open_can_bus("memory:fanout");
    auto b = open_can_bus("memory:fanout");
    auto c = open_can_bus("memory:fanout");
    auto other = open_can_bus("memory:elsewhere");
    EXPECT_EQ(a->name(), "memory:fanout");

    const nav::CanFrame f = frame(0x607, 0xF8);
    ASSERT_TRUE(a->send(f));
    nav::CanFrame got;
    std::int64_t host_ns = 0;
    for (auto* bus : {b.get(), c.get()}) {
        ASSERT_EQ(bus->receive(got, host_ns, 1s), RxStatus::Frame);
        EXPECT_EQ(got, f);
        EXPECT_GT(host_ns, 0);
        EXPECT_EQ(bus->counters().rx_frames, 1u);
    }
    EXPECT_EQ(a->receive(got, host_ns, 10ms), RxStatus::Timeout);      // not its own
    EXPECT_EQ(other->receive(got, host_ns, 10ms), RxStatus::Timeout);  // another name
    EXPECT_EQ(a->counters().tx_frames, 1u);
    EXPECT_EQ(a->counters().rx_frames, 0u);
}

TEST(MemoryBus, preserves_send_order_and_frame_fields) {
    auto tx = open_can_bus("memory:order");
    auto rx = open_can_bus("memory:order");
    std::vector<nav::CanFrame> sent;
    for (std::uint32_t i = 0; i < 100; ++i) {
        nav::CanFrame f = frame(0x18FF50E5 + i, static_cast<std::uint8_t>(i), true);
        if (i % 10 == 0) {
            f.rtr = true;
            f.len = 0;
            f.data = {};
        }
        sent.push_back(f);
        ASSERT_TRUE(tx->send(f));
    }
    for (const auto& want : sent) {
        nav::CanFrame got;
        std::int64_t t = 0;
        ASSERT_EQ(rx->receive(got, t, 1s), RxStatus::Frame);
        EXPECT_EQ(got, want);
    }
}

TEST(MemoryBus, rejects_invalid_frames_and_counts_them) {
    auto tx = open_can_bus("memory:invalid");
    nav::CanFrame too_long = frame(0x100, 1);
    too_long.len = 9;
    nav::CanFrame wide_std = frame(0x800, 1);  // 12 bits in an 11-bit id
    nav::CanFrame wide_ext = frame(0x20000000, 1, true);
    EXPECT_FALSE(tx->send(too_long));
    EXPECT_FALSE(tx->send(wide_std));
    EXPECT_FALSE(tx->send(wide_ext));
    EXPECT_EQ(tx->counters().tx_failed, 3u);
    EXPECT_EQ(tx->counters().tx_frames, 0u);
}

TEST(MemoryBus, error_frames_are_reported_and_bus_off_counted) {
    auto tx = open_can_bus("memory:errors");
    auto rx = open_can_bus("memory:errors");
    nav::CanFrame busoff;
    busoff.error = true;
    busoff.id = err::kBusOff;
    busoff.len = 8;
    nav::CanFrame passive;
    passive.error = true;
    passive.id = err::kController;
    passive.len = 8;
    passive.data[1] = err::kCtrlRxPassive;
    ASSERT_TRUE(tx->send(passive));
    ASSERT_TRUE(tx->send(busoff));
    nav::CanFrame got;
    std::int64_t t = 0;
    ASSERT_EQ(rx->receive(got, t, 1s), RxStatus::ErrorFrame);
    EXPECT_EQ(got.data[1], err::kCtrlRxPassive);
    ASSERT_EQ(rx->receive(got, t, 1s), RxStatus::ErrorFrame);
    EXPECT_EQ(got.id, err::kBusOff);
    const BusCounters c = rx->counters();
    EXPECT_EQ(c.error_frames, 2u);
    EXPECT_EQ(c.bus_off, 1u);
    EXPECT_EQ(c.rx_frames, 0u);
}

TEST(MemoryBus, receive_times_out_then_wakes_for_a_frame_from_another_thread) {
    auto tx = open_can_bus("memory:threads");
    auto rx = open_can_bus("memory:threads");
    nav::CanFrame got;
    std::int64_t t = 0;
    EXPECT_EQ(rx->receive(got, t, 5ms), RxStatus::Timeout);
    EXPECT_EQ(rx->receive(got, t, 0ns), RxStatus::Timeout);

    // A producer thread sends 2000 frames while this thread receives with deadlines.
    constexpr int kFrames = 2000;
    std::thread producer([&] {
        for (int i = 0; i < kFrames; ++i)
            tx->send(frame(static_cast<std::uint32_t>(i & 0x7FF), static_cast<std::uint8_t>(i)));
    });
    int received = 0;
    int out_of_order = 0;
    for (int i = 0; i < kFrames; ++i) {
        if (rx->receive(got, t, 5s) != RxStatus::Frame) break;
        if (got.id != static_cast<std::uint32_t>(i & 0x7FF)) ++out_of_order;
        ++received;
    }
    producer.join();
    EXPECT_EQ(received, kFrames);
    EXPECT_EQ(out_of_order, 0);
    EXPECT_EQ(tx->counters().tx_frames, static_cast<std::uint64_t>(kFrames));
}

TEST(MemoryBus, a_full_receiver_drops_new_frames_and_counts_overruns) {
    auto tx = open_can_bus("memory:overrun");
    auto rx = open_can_bus("memory:overrun");
    for (std::size_t i = 0; i < kMemoryBusQueue + 5; ++i) tx->send(frame(0x123, 0));
    EXPECT_EQ(rx->counters().rx_overruns, 5u);
    EXPECT_EQ(tx->counters().tx_frames, kMemoryBusQueue + 5);
}

TEST(MemoryBus, a_name_is_free_again_after_its_buses_close) {
    {
        auto a = open_can_bus("memory:reuse");
        auto b = open_can_bus("memory:reuse");
        a->send(frame(0x1, 1));  // left unread in b's queue
    }
    auto a = open_can_bus("memory:reuse");
    auto b = open_can_bus("memory:reuse");
    nav::CanFrame got;
    std::int64_t t = 0;
    EXPECT_EQ(b->receive(got, t, 5ms), RxStatus::Timeout);  // nothing left from before
}

}  // namespace
}  // namespace mirage::can
