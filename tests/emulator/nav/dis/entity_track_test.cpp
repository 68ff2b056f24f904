// SPDX-License-Identifier: Apache-2.0
// A DIS entity followed as a navigation source (docs/dis.md §6): timestamps placed in time,
// dead reckoning to the present every step, the timeout, reordered PDUs, the entity lock, and a
// sample through a PDU and back.
#include "mirage/dis/entity_track.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <vector>

#include "dis_fixtures.hpp"
#include "mirage/dis/dead_reckoning.hpp"
#include "mirage/dis/dis_sample.hpp"

namespace mirage::dis {
namespace {

using namespace std::chrono_literals;

// 2026-11-28 10:59:59.900 UTC.
const core::GpsTime kNow = core::parse_time("2026-11-28T10:59:59.9Z");

std::vector<std::uint8_t> pdu(EntityState s, double seconds_past_hour, bool absolute = true) {
    s.timestamp = encode_timestamp(seconds_past_hour, absolute);
    return encode(s);
}

double ns_between(core::GpsTime a, core::GpsTime b) { return double((b - a).count()); }

// One DIS time unit is 3600 s / 2³¹ ≈ 1.68 µs: resolved times are compared to that.
constexpr double kUnitNs = 3600e9 / 2147483648.0;

TEST(DisTrack, absolute_timestamps_land_in_the_hour_nearest_the_host_clock) {
    EntityTrack track;
    // 0.05 s past the next hour, heard 0.15 s before it, and 59:59.0 of this hour.
    EXPECT_NEAR(ns_between(kNow, track.resolve(encode_timestamp(0.05, true), kNow)), 150e6,
                kUnitNs);
    EXPECT_NEAR(ns_between(kNow, track.resolve(encode_timestamp(3599.0, true), kNow)), -900e6,
                kUnitNs);
}

TEST(DisTrack, relative_timestamps_unwrap_the_hour_and_ignore_late_arrivals) {
    EntityTrack track;
    // Sender's clock: 3599.5 s, then across its hourly rollover; arrivals 2 ms, 9 ms (late)
    // and 2 ms after the send.
    const double ts[] = {3599.5, 0.5, 1.5};
    const core::Nanos delay[] = {2ms, 9ms, 2ms};
    std::vector<core::GpsTime> got;
    for (int i = 0; i < 3; ++i) {
        const core::GpsTime sent = kNow + std::chrono::seconds(i);
        got.push_back(track.resolve(encode_timestamp(ts[i], false), sent + delay[i]));
    }
    // Placed by the lower envelope of arrival − sender time: 2 ms after the send.
    EXPECT_NEAR(ns_between(kNow, got[0]), 2e6, kUnitNs);
    EXPECT_NEAR(ns_between(kNow, got[1]), 1e9 + 2e6, kUnitNs);
    EXPECT_NEAR(ns_between(kNow, got[2]), 2e9 + 2e6, kUnitNs);
}

TEST(DisTrack, samples_follow_the_dead_reckoned_path_every_step) {
    EntityTrack track;
    EntityState s = moving(8);  // RVB: every term turns with the body
    s.location = {4'000'000.0, 700'000.0, 4'900'000.0};
    std::vector<nav::NavSample> out;
    const auto fn = [&](const nav::NavSample& x) { out.push_back(x); };
    // Stamped 10 ms before it arrives.
    track.feed(pdu(s, utc_seconds_past_hour(kNow - 10ms)), kNow, fn);
    ASSERT_EQ(out.size(), 1u);
    track.tick(kNow + 4ms, fn);  // under the 5 ms step: nothing
    EXPECT_EQ(out.size(), 1u);
    track.tick(kNow + 1500ms, fn);
    ASSERT_EQ(out.size(), 2u);
    // The PDU's time as its timestamp gives it (within a DIS unit of kNow − 10 ms).
    const core::GpsTime t0 =
        EntityTrack().resolve(encode_timestamp(utc_seconds_past_hour(kNow - 10ms), true), kNow);
    EXPECT_NEAR(ns_between(kNow - 10ms, t0), 0, kUnitNs);
    const double dt = double((kNow + 1500ms - t0).count()) * 1e-9;
    const nav::NavSample want = to_sample(dead_reckon(s, dt), kNow + 1500ms);
    EXPECT_EQ(out[1].t, kNow + 1500ms);
    EXPECT_NEAR(out[1].lat_deg, want.lat_deg, 1e-10);
    EXPECT_NEAR(out[1].lon_deg, want.lon_deg, 1e-10);
    EXPECT_NEAR(out[1].height_m, want.height_m, 1e-5);
    EXPECT_NEAR(out[1].heading_rad, want.heading_rad, 1e-9);
    EXPECT_NEAR(out[1].pitch_rad, want.pitch_rad, 1e-9);
    EXPECT_NEAR(out[1].roll_rad, want.roll_rad, 1e-9);
    // The entity did move: 1.5 s of 13 m/s is no rounding.
    EXPECT_GT(std::abs(out[1].lat_deg - out[0].lat_deg) + std::abs(out[1].lon_deg - out[0].lon_deg),
              1e-5);
    EXPECT_EQ(track.counters().samples, 2u);
}

TEST(DisTrack, a_silent_entity_times_out_and_comes_back_with_its_next_pdu) {
    TrackConfig c;
    c.timeout = 12s;
    EntityTrack track(c);
    std::vector<nav::NavSample> out;
    const auto fn = [&](const nav::NavSample& x) { out.push_back(x); };
    track.feed(pdu(moving(2), utc_seconds_past_hour(kNow)), kNow, fn);
    track.tick(kNow + 11s, fn);
    EXPECT_EQ(out.size(), 2u);
    EXPECT_FALSE(track.timed_out(kNow + 12s));
    EXPECT_TRUE(track.timed_out(kNow + 12s + 1ms));
    track.tick(kNow + 13s, fn);
    track.tick(kNow + 14s, fn);
    EXPECT_EQ(out.size(), 2u);
    EXPECT_EQ(track.track_counters().timeouts, 1u);  // one silent period, counted once
    track.feed(pdu(moving(2), utc_seconds_past_hour(kNow + 15s)), kNow + 15s, fn);
    track.tick(kNow + 16s, fn);
    EXPECT_EQ(out.size(), 4u);
}

TEST(DisTrack, an_older_pdu_is_counted_and_does_not_replace_the_base) {
    EntityTrack track;
    std::vector<nav::NavSample> out;
    const auto fn = [&](const nav::NavSample& x) { out.push_back(x); };
    EntityState a = moving(2), b = moving(2);
    b.location.x() += 100;
    track.feed(pdu(a, utc_seconds_past_hour(kNow)), kNow, fn);
    track.feed(pdu(b, utc_seconds_past_hour(kNow - 1s)), kNow + 10ms, fn);
    EXPECT_EQ(track.track_counters().out_of_order, 1u);
    EXPECT_EQ(track.track_counters().accepted, 1u);
    EXPECT_EQ(out.size(), 1u);
}

TEST(DisTrack, without_an_entity_the_first_one_heard_is_followed) {
    EntityTrack track;
    const auto fn = [](const nav::NavSample&) {};
    EntityState a = moving(2), b = moving(2);
    a.id = {1, 2, 3};
    b.id = {1, 2, 4};
    track.feed(pdu(a, utc_seconds_past_hour(kNow)), kNow, fn);
    track.feed(pdu(b, utc_seconds_past_hour(kNow)), kNow + 1ms, fn);
    ASSERT_TRUE(track.entity());
    EXPECT_EQ(*track.entity(), (EntityId{1, 2, 3}));
    EXPECT_EQ(track.dis_counters().other_entity, 1u);
    EXPECT_EQ(track.track_counters().accepted, 1u);
}

// from_sample -> bytes -> decode -> to_sample gives the sample back (float32 angles and velocity).
TEST(DisTrack, a_sample_through_a_pdu_and_back) {
    nav::NavSample s;
    s.t = kNow;
    s.fields = nav::NavSample::kTime | nav::NavSample::kPosition | nav::NavSample::kAttitude |
               nav::NavSample::kVelocity | nav::NavSample::kAngularRate;
    s.lat_deg = 48.137;
    s.lon_deg = 11.575;
    s.height_m = 519.5;
    s.heading_rad = 200 * std::numbers::pi / 180;
    s.pitch_rad = 0.17;
    s.roll_rad = -0.09;
    s.velocity_ned_mps = {-12.0, 3.5, 0.25};
    s.rate_frd_radps = {0.01, -0.02, 0.3};
    const EntityState e = from_sample(s, {7, 8, 9}, 4);
    EXPECT_EQ(e.dr_algorithm, 7);
    EntityStateDecoder d;
    EntityState back;
    ASSERT_EQ(d.decode(encode(e), back), Status::Ok);
    EXPECT_EQ(back.id, (EntityId{7, 8, 9}));
    EXPECT_EQ(back.exercise, 4);
    const auto ts = decode_timestamp(back.timestamp);
    EXPECT_TRUE(ts.absolute);
    EXPECT_NEAR(ts.seconds_past_hour, 3599.9, 2e-6);
    const nav::NavSample r = to_sample(dead_reckon(back, 0), s.t);
    EXPECT_NEAR(r.lat_deg, s.lat_deg, 1e-10);
    EXPECT_NEAR(r.lon_deg, s.lon_deg, 1e-10);
    EXPECT_NEAR(r.height_m, s.height_m, 1e-6);
    EXPECT_NEAR(r.heading_rad, s.heading_rad, 1e-6);
    EXPECT_NEAR(r.pitch_rad, s.pitch_rad, 1e-6);
    EXPECT_NEAR(r.roll_rad, s.roll_rad, 1e-6);
    EXPECT_LT((r.velocity_ned_mps - s.velocity_ned_mps).norm(), 1e-5);
    EXPECT_LT((back.dr_angular_velocity.cast<double>() - s.rate_frd_radps).norm(), 1e-7);
}

}  // namespace
}  // namespace mirage::dis
