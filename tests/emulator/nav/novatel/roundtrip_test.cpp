// SPDX-License-Identifier: Apache-2.0
// NavSample -> NovatelEncoder -> NovatelDecoder -> NavSample for random samples.
#include <gtest/gtest.h>

#include <cmath>

#include "frames.hpp"
#include "mirage/novatel/encoder.hpp"
#include "sample_gen.hpp"

namespace {

using namespace mirage::novatel;
using namespace mirage::novatel::test;
using mirage::nav::NavSample;

void expect_pva(const NavSample& in, const NavSample& out, double height_tol) {
    EXPECT_EQ(out.lat_deg, in.lat_deg);
    EXPECT_EQ(out.lon_deg, in.lon_deg);
    EXPECT_NEAR(out.height_m, in.height_m, height_tol);
    EXPECT_NEAR((out.velocity_ned_mps - in.velocity_ned_mps).norm(), 0.0, 1e-12);
    EXPECT_NEAR(out.roll_rad, in.roll_rad, 1e-13);
    EXPECT_NEAR(out.pitch_rad, in.pitch_rad, 1e-13);
    EXPECT_NEAR(out.heading_rad, in.heading_rad, 1e-13);
}

TEST(NovatelRoundTrip, random_samples_survive_all_three_logs) {
    std::mt19937_64 rng(42);
    EncoderOptions opt;
    opt.undulation_m = -23.25F;
    NovatelEncoder enc(opt);
    int n = 0;
    for (int i = 0; i < 300; ++i) {
        const NavSample in = random_sample(rng);
        const auto x = decode(enc.inspvax(in));
        const auto s = decode(enc.inspvas(in));
        const auto b = decode(enc.bestpos(in));
        ASSERT_EQ(x.size(), 1U);
        ASSERT_EQ(s.size(), 1U);
        ASSERT_EQ(b.size(), 1U);
        for (const NavSample* o : {&x[0], &s[0], &b[0]}) {
            EXPECT_EQ(o->t, in.t);  // whole ms: exact in the header and in INSPVAS's f64
            EXPECT_EQ(o->source, mirage::nav::Protocol::Novatel);
        }
        EXPECT_EQ(x[0].fields, in.fields);
        EXPECT_EQ(s[0].fields, in.fields);
        EXPECT_EQ(b[0].fields, NavSample::kTime | NavSample::kPosition);
        expect_pva(in, x[0], 1e-9);  // MSL − N + N
        expect_pva(in, s[0], 0.0);
        EXPECT_NEAR(b[0].height_m, in.height_m, 1e-9);
        EXPECT_EQ(x[0].quality, in.quality);
        EXPECT_EQ(b[0].quality, in.quality);
        ++n;
    }
    EXPECT_EQ(n, 300);
}

TEST(NovatelRoundTrip, inspvas_keeps_sub_millisecond_time_to_the_nanosecond) {
    std::mt19937_64 rng(7);
    NovatelEncoder enc;
    for (int i = 0; i < 200; ++i) {
        NavSample in = random_sample(rng);
        in.t += mirage::core::Nanos(static_cast<std::int64_t>(rng() % 1'000'000));
        const auto s = decode(enc.inspvas(in));
        ASSERT_EQ(s.size(), 1U);
        EXPECT_LE(std::abs((s[0].t - in.t).count()), 1);
    }
}

TEST(NovatelRoundTrip, heading_only_sample_writes_azimuth_with_zero_roll_and_pitch) {
    NavSample in;
    in.fields = NavSample::kTime | NavSample::kPosition | NavSample::kHeading;
    in.t = mirage::core::from_week_time(2300, 5'000'000'000);
    in.heading_rad = 1.0;
    in.roll_rad = 0.3;  // not valid: must not be written
    in.quality = mirage::nav::FixQuality::RtkFixed;
    NovatelEncoder enc;
    const auto s = decode(enc.inspvax(in));
    ASSERT_EQ(s.size(), 1U);
    EXPECT_NEAR(s[0].heading_rad, 1.0, 1e-14);
    EXPECT_EQ(s[0].roll_rad, 0.0);
}

TEST(NovatelRoundTrip, sample_without_time_is_sent_with_unknown_time_status) {
    NavSample in;
    in.fields = NavSample::kPosition;
    in.lat_deg = 1.0;
    in.quality = mirage::nav::FixQuality::Autonomous;
    NovatelEncoder enc;
    const auto b = decode(enc.bestpos(in));
    const auto s = decode(enc.inspvas(in));
    ASSERT_EQ(b.size(), 1U);
    ASSERT_EQ(s.size(), 1U);
    EXPECT_FALSE(b[0].has(NavSample::kTime));
    EXPECT_FALSE(s[0].has(NavSample::kTime));
    EXPECT_EQ(b[0].lat_deg, 1.0);
}

}  // namespace
