// SPDX-License-Identifier: Apache-2.0
// NCOM time: GPS minutes from status channel 0 + ms into the minute (docs/nav-protocols.md §3,
// §12).
#include <gtest/gtest.h>

#include "ncom_util.hpp"

namespace {

using namespace mirage::ncom;
using namespace mirage::ncom::test;
using mirage::nav::NavSample;

constexpr std::int64_t kNsPerMinute = 60'000'000'000LL;

// A locked packet at `ms` of the minute carrying `channel` (channel 0 with `minutes`).
std::array<std::uint8_t, kPacketSize> packet(std::uint16_t ms, std::uint8_t channel,
                                             std::int32_t minutes) {
    Packet p;
    p.ms_of_minute = ms;
    p.nav_status = kNavLocked;
    p.lat_rad = 0.5;
    p.channel = channel;
    if (channel == 0) {
        Channel0 c;
        c.gps_minutes = minutes;
        c.position_mode = kModeRtkInteger;
        p.status = pack_channel0(c);
    }
    return pack(p);
}

TEST(NcomTime, packets_before_channel_0_are_counted_and_not_emitted) {
    // Start listening mid-rotation (channels 0,1,2): packets 1 and 2 have no minute yet.
    const auto pkts = make_packets(6, 1, kT0);
    Collect c;
    for (std::size_t i = 1; i < pkts.size(); ++i) c.feed(pkts[i]);
    EXPECT_EQ(c.dec.ncom_counters().no_time, 2U);
    ASSERT_EQ(c.out.size(), 3U);
    EXPECT_EQ(c.out[0].t.time_since_epoch().count(), kT0 + 30'000'000);
    EXPECT_TRUE(c.out[0].has(NavSample::kTime));
}

TEST(NcomTime, minute_carries_over_when_the_ms_wrap_between_channel_0_packets) {
    const std::int32_t m = 24'598'200;
    Collect c;
    c.feed(packet(59'990, 0, m));
    c.feed(packet(0, 1, 0));  // next minute, no channel 0
    c.feed(packet(10, 2, 0));
    c.feed(packet(20, 0, m + 1));  // channel 0 agrees
    ASSERT_EQ(c.out.size(), 4U);
    const std::int64_t base = static_cast<std::int64_t>(m) * kNsPerMinute;
    EXPECT_EQ(c.out[0].t.time_since_epoch().count(), base + 59'990'000'000LL);
    EXPECT_EQ(c.out[1].t.time_since_epoch().count(), base + kNsPerMinute);
    EXPECT_EQ(c.out[2].t.time_since_epoch().count(), base + kNsPerMinute + 10'000'000);
    EXPECT_EQ(c.out[3].t.time_since_epoch().count(), base + kNsPerMinute + 20'000'000);
    EXPECT_EQ(c.out[3].quality, mirage::nav::FixQuality::RtkFixed);
}

TEST(NcomTime, week_end_and_1024_week_rollover_are_continuous) {
    for (std::int32_t week : {1023, 2047, 2440}) {
        const std::int32_t last_minute = (week + 1) * 10'080 - 1;
        Collect c;
        c.feed(packet(59'999, 0, last_minute));
        c.feed(packet(0, 1, 0));
        ASSERT_EQ(c.out.size(), 2U);
        EXPECT_EQ((c.out[1].t - c.out[0].t).count(), 1'000'000) << week;
        const auto wt = mirage::core::to_week_time(c.out[1].t);
        EXPECT_EQ(wt.week, week + 1);
        EXPECT_EQ(wt.ns_of_week, 0);
    }
}

TEST(NcomTime, encoder_splits_time_into_minute_and_ms_across_a_week_boundary) {
    const std::int64_t week_end = 2048LL * 604'800 * 1'000'000'000LL;
    NcomEncoder enc(EncoderOptions{{0}});
    NavSample s;
    s.fields = NavSample::kTime | NavSample::kPosition;
    s.quality = mirage::nav::FixQuality::RtkFixed;
    Collect c;
    for (std::int64_t dt : {-2'000'000LL, -1'000'000LL, 0LL, 1'000'000LL}) {
        s.t = mirage::core::GpsTime(mirage::core::Nanos(week_end + dt));
        const Packet p = enc.to_packet(s, 0);
        EXPECT_EQ(p.ms_of_minute, dt < 0 ? 60'000 + dt / 1'000'000 : dt / 1'000'000);
        c.feed(enc.encode(s));
    }
    ASSERT_EQ(c.out.size(), 4U);
    EXPECT_EQ(c.out[2].t.time_since_epoch().count(), week_end);
    EXPECT_EQ(mirage::core::to_week_time(c.out[3].t).week, 2048);
    EXPECT_EQ(mirage::core::to_week_time(c.out[1].t).week, 2047);
}

TEST(NcomTime, negative_or_absurd_channel_0_minutes_reject_the_packet) {
    Collect c;
    c.feed(packet(0, 0, -5));
    c.feed(packet(10, 0, 2'000'000'000));  // year ~5800: corrupt
    EXPECT_TRUE(c.out.empty());
    EXPECT_EQ(c.dec.counters().invalid_field, 2U);
    EXPECT_FALSE(c.dec.has_time());
}

}  // namespace
