// SPDX-License-Identifier: Apache-2.0
// NavSample -> NcomEncoder -> NcomDecoder -> NavSample within NCOM's quantisation.
#include <gtest/gtest.h>

#include <cmath>

#include "mirage/core/error.hpp"
#include "ncom_util.hpp"

namespace {

using namespace mirage::ncom;
using namespace mirage::ncom::test;
using mirage::nav::FixQuality;
using mirage::nav::NavSample;

TEST(NcomRoundTrip, random_samples_come_back_within_quantisation) {
    std::mt19937_64 rng(1);
    NcomEncoder enc;
    Collect c;
    std::vector<NavSample> in;
    for (int i = 0; i < 500; ++i) {
        // Sub-ms times: rounded to the nearest ms.
        in.push_back(random_sample(rng, kT0 + i * 10'000'000LL + 300'000));
        c.feed(enc.encode(in.back()));
    }
    ASSERT_EQ(c.out.size(), in.size());
    for (std::size_t i = 0; i < in.size(); ++i) {
        const NavSample& a = in[i];
        const NavSample& b = c.out[i];
        EXPECT_EQ(b.fields, a.fields);
        EXPECT_EQ((b.t - a.t).count(), -300'000);
        EXPECT_NEAR(b.lat_deg, a.lat_deg, 1e-12);
        EXPECT_NEAR(b.lon_deg, a.lon_deg, 1e-12);
        EXPECT_NEAR(b.height_m, a.height_m, 1.3e-4);  // f32: half an ulp at < 4 km
        EXPECT_LE((b.velocity_ned_mps - a.velocity_ned_mps).cwiseAbs().maxCoeff(), 0.5e-4 + 1e-12);
        EXPECT_LE((b.accel_frd_mps2 - a.accel_frd_mps2).cwiseAbs().maxCoeff(), 0.5e-4 + 1e-12);
        EXPECT_LE((b.rate_frd_radps - a.rate_frd_radps).cwiseAbs().maxCoeff(), 0.5e-5 + 1e-12);
        // Heading may come back across the 0/2π seam.
        const double dh = std::remainder(b.heading_rad - a.heading_rad, 2 * std::numbers::pi);
        EXPECT_LE(std::abs(dh), 0.5e-6 + 1e-12);
        EXPECT_GE(b.heading_rad, 0.0);
        EXPECT_LT(b.heading_rad, 2 * std::numbers::pi);
        EXPECT_LE(std::abs(b.pitch_rad - a.pitch_rad), 0.5e-6 + 1e-12);
        EXPECT_LE(std::abs(b.roll_rad - a.roll_rad), 0.5e-6 + 1e-12);
        // Satellites and GNSS mode ride on channel 0 (every 3rd packet here): the latest
        // channel-0 values apply.
        EXPECT_EQ(b.quality, in[i - i % 3].quality);
        EXPECT_EQ(b.satellites, in[i - i % 3].satellites);
    }
}

TEST(NcomRoundTrip, heading_350_is_sent_as_minus_10_and_read_back_as_350) {
    NavSample s;
    s.fields = NavSample::kTime | NavSample::kPosition | NavSample::kAttitude;
    s.t = mirage::core::GpsTime(mirage::core::Nanos(kT0));
    s.heading_rad = 350.0 * std::numbers::pi / 180.0;
    s.quality = FixQuality::RtkFixed;
    NcomEncoder enc;
    const Packet p = enc.to_packet(s, 0);
    EXPECT_EQ(p.heading,
              static_cast<std::int32_t>(std::lround(-10.0 * std::numbers::pi / 180 * 1e6)));
    Collect c;
    c.feed(pack(p));
    ASSERT_EQ(c.out.size(), 1U);
    EXPECT_NEAR(c.out[0].heading_rad, 350.0 * std::numbers::pi / 180.0, 0.5e-6);
}

TEST(NcomRoundTrip, missing_fields_are_sent_invalid_and_left_out_on_decode) {
    NavSample s;
    s.fields = NavSample::kTime | NavSample::kPosition | NavSample::kHeading;
    s.t = mirage::core::GpsTime(mirage::core::Nanos(kT0));
    s.heading_rad = 1.0;
    s.quality = FixQuality::Autonomous;
    NcomEncoder enc;
    const Packet p = enc.to_packet(s, 0);
    EXPECT_EQ(p.accel[0], kInvalidI24);
    EXPECT_EQ(p.rate[2], kInvalidI24);
    EXPECT_EQ(p.vel_ned[1], kInvalidI24);
    EXPECT_EQ(p.pitch, kInvalidI24);
    EXPECT_EQ(p.heading, 1'000'000);
    Collect c;
    c.feed(pack(p));
    ASSERT_EQ(c.out.size(), 1U);
    // Heading alone is not an attitude: NCOM has no heading-only flag, so it is dropped too.
    EXPECT_EQ(c.out[0].fields, NavSample::kTime | NavSample::kPosition);
}

TEST(NcomRoundTrip, msl_option_marks_the_height) {
    const auto pkts = make_packets(1, 3, kT0);
    NcomDecoder dec(DecoderOptions{.altitude_is_msl = true});
    std::vector<NavSample> out;
    dec.feed(pkts[0], [&](const NavSample& s) { out.push_back(s); });
    ASSERT_EQ(out.size(), 1U);
    EXPECT_TRUE(out[0].has(NavSample::kHeightIsMsl));
}

TEST(NcomRoundTrip, encoder_sends_channel_0_at_least_every_5th_packet) {
    for (const std::vector<std::uint8_t>& chans :
         {std::vector<std::uint8_t>{0, 1, 2}, std::vector<std::uint8_t>{0, 1, 2, 3, 4},
          std::vector<std::uint8_t>{1, 0, 2, 3, 0, 4, 5}}) {
        NcomEncoder enc(EncoderOptions{chans});
        std::mt19937_64 rng(5);
        int since0 = 0;
        int max_gap = 0;
        for (int i = 0; i < 50; ++i) {
            const auto b = enc.encode(random_sample(rng, kT0));
            since0 = b[62] == 0 ? 0 : since0 + 1;
            max_gap = std::max(max_gap, since0);
            EXPECT_EQ(b[62], chans[static_cast<std::size_t>(i) % chans.size()]);
        }
        EXPECT_LE(max_gap, 4);
    }
    EXPECT_THROW(NcomEncoder(EncoderOptions{{0, 1, 2, 3, 4, 5}}), mirage::ConfigError);
    EXPECT_THROW(NcomEncoder(EncoderOptions{{1, 2}}), mirage::ConfigError);
    EXPECT_THROW(NcomEncoder(EncoderOptions{{}}), mirage::ConfigError);
}

TEST(NcomRoundTrip, position_modes_map_to_fix_quality) {
    EXPECT_EQ(quality_from_position_mode(kModeSps), FixQuality::Autonomous);
    EXPECT_EQ(quality_from_position_mode(kModeDifferential), FixQuality::Differential);
    EXPECT_EQ(quality_from_position_mode(kModeRtkFloat), FixQuality::RtkFloat);
    EXPECT_EQ(quality_from_position_mode(kModeRtkInteger), FixQuality::RtkFixed);
    EXPECT_EQ(quality_from_position_mode(kModeNone), FixQuality::DeadReckoning);
    EXPECT_EQ(quality_from_position_mode(200), FixQuality::Unknown);
}

}  // namespace
