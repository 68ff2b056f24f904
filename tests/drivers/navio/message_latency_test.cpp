// SPDX-License-Identifier: Apache-2.0
// INS message -> first data packet rendered with a pose from it: the live loop's bookkeeping.
#include "mirage/navio/message_latency.hpp"

#include <gtest/gtest.h>

namespace mirage::test {
namespace {

using navpose::Track;

navio::AppliedMessage msg(std::uint64_t seq, std::int64_t arrival_us, bool pos, bool att) {
    return {{seq, arrival_us * 1000}, pos, att};
}
navpose::UsedMessage used(std::uint64_t seq, Track track) { return {{seq, 0}, track}; }
constexpr std::int64_t us(std::int64_t v) { return v * 1000; }

TEST(MessageLatency, times_each_message_by_the_first_packet_rendered_with_it) {
    navio::MessageLatency l;
    l.applied({msg(1, 1000, true, false), msg(2, 1100, false, true)});
    // A packet sent before any window used them times nothing.
    l.data_packet_sent(us(1200));
    EXPECT_EQ(l.latency().count(), 0u);
    // A window uses both; its pulses wait for the next window's packet.
    l.rendered({used(1, Track::Position), used(2, Track::Attitude)});
    l.rendered({used(1, Track::Position), used(2, Track::Attitude)});  // used again: once
    l.data_packet_sent(us(1500));
    ASSERT_EQ(l.latency().count(), 2u);
    EXPECT_EQ(l.latency().worst(), core::Nanos(us(500)));  // message 1: 1000 -> 1500 µs
    EXPECT_EQ(l.latency().best(), core::Nanos(us(400)));   // message 2: 1100 -> 1500 µs
    // Later packets with the same messages time nothing again.
    l.rendered({used(1, Track::Position), used(2, Track::Attitude)});
    l.data_packet_sent(us(9000));
    EXPECT_EQ(l.latency().count(), 2u);
    EXPECT_EQ(l.messages(), 2u);
    EXPECT_EQ(l.unused().superseded + l.unused().waiting, 0u);
}

TEST(MessageLatency, a_backlog_is_not_timed_and_unused_messages_say_why) {
    navio::MessageLatency l;
    // Message 7 was applied before timing began (never passed to applied()): not timed.
    l.applied({msg(8, 2000, true, false), msg(9, 2010, true, false), msg(10, 2020, false, true),
               msg(11, 2030, true, true)});
    // Extrapolation from the newest position (9) and attitude (10): 8 was superseded.
    l.rendered({used(7, Track::Position), used(9, Track::Position), used(10, Track::Attitude)});
    l.data_packet_sent(us(2100));
    EXPECT_EQ(l.latency().count(), 2u);  // 9 and 10; 7 is the backlog's
    // 11 arrived too late for any window: still waiting when the run ends.
    const auto u = l.unused();
    EXPECT_EQ(u.superseded, 1u);
    EXPECT_EQ(u.waiting, 1u);
    EXPECT_EQ(l.messages(), 4u);
}

TEST(MessageLatency, a_message_rendered_but_not_yet_sent_is_waiting_not_superseded) {
    navio::MessageLatency l;
    l.applied({msg(1, 0, true, false), msg(2, 10, true, false)});
    l.rendered({used(1, Track::Position), used(2, Track::Position)});  // interpolation: both
    // No packet before the end.
    EXPECT_EQ(l.unused().waiting, 2u);
    EXPECT_EQ(l.unused().superseded, 0u);
}

}  // namespace
}  // namespace mirage::test
