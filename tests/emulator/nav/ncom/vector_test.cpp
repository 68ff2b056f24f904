// SPDX-License-Identifier: Apache-2.0
// The NCOM vector of docs/nav-protocols.md §3: decodes to its values, and our encoder rebuilds it.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "mirage/core/time.hpp"
#include "mirage/ncom/decoder.hpp"
#include "mirage/ncom/encoder.hpp"

namespace {

using namespace mirage::ncom;
using mirage::nav::FixQuality;
using mirage::nav::NavSample;

constexpr double kDeg = std::numbers::pi / 180.0;

std::vector<std::uint8_t> from_hex(const std::string& hex) {
    std::vector<std::uint8_t> out;
    for (std::size_t i = 0; i + 1 < hex.size(); i += 2)
        out.push_back(static_cast<std::uint8_t>(std::stoi(hex.substr(i, 2), nullptr, 16)));
    return out;
}

const std::vector<std::uint8_t> kVector = from_hex(
    "e7d204881300000000cc80fe00000000000000000004bf55dad863afdfea3f90a15d9082bac93f9a590844a0860100"
    "0000000000227a16e9ddffd05100ff00b85677010c0404049c");

// GPS week 2440, minute 3000 of the week, 1234 ms into the minute.
const std::int64_t kVectorNs = (24'598'200LL * 60 + 1) * 1'000'000'000LL + 234'000'000LL;

NavSample vector_sample() {
    NavSample s;
    s.fields = NavSample::kTime | NavSample::kPosition | NavSample::kVelocity |
               NavSample::kAttitude | NavSample::kAcceleration | NavSample::kAngularRate;
    s.t = mirage::core::GpsTime(mirage::core::Nanos(kVectorNs));
    s.lat_deg = 48.1173;
    s.lon_deg = 11.5167;
    s.height_m = 545.4;
    s.velocity_ned_mps = {10.0, 0.0, 0.0};
    s.heading_rad = 84.40 * kDeg;
    s.pitch_rad = -0.50 * kDeg;
    s.roll_rad = 1.20 * kDeg;
    s.accel_frd_mps2 = {0.5, 0.0, -9.81};
    s.rate_frd_radps = {0.0, 0.0, 0.0};
    s.satellites = 12;
    s.quality = FixQuality::Differential;
    return s;
}

TEST(NcomVector, has_72_bytes_and_the_three_stated_checksums) {
    ASSERT_EQ(kVector.size(), kPacketSize);
    const std::span<const std::uint8_t, kPacketSize> p(kVector.data(), kPacketSize);
    EXPECT_EQ(checksum(p, 1), 0xBF);
    EXPECT_EQ(checksum(p, 2), 0xFF);
    EXPECT_EQ(checksum(p, 3), 0x9C);
    EXPECT_TRUE(checksums_ok(p));
}

TEST(NcomVector, decodes_to_exactly_its_values) {
    NcomDecoder dec;
    std::vector<NavSample> out;
    dec.feed(kVector, [&](const NavSample& s) { out.push_back(s); });
    ASSERT_EQ(out.size(), 1U);
    const NavSample& s = out[0];
    EXPECT_EQ(s.source, mirage::nav::Protocol::Ncom);
    EXPECT_EQ(s.fields, vector_sample().fields);
    EXPECT_EQ(s.t.time_since_epoch().count(), kVectorNs);
    const auto wt = mirage::core::to_week_time(s.t);
    EXPECT_EQ(wt.week, 2440);
    EXPECT_EQ(wt.ns_of_week, (3000LL * 60 + 1) * 1'000'000'000LL + 234'000'000LL);
    EXPECT_NEAR(s.lat_deg, 48.1173, 1e-12);
    EXPECT_NEAR(s.lon_deg, 11.5167, 1e-12);
    EXPECT_EQ(s.height_m, static_cast<double>(545.4F));
    EXPECT_EQ(s.velocity_ned_mps, Eigen::Vector3d(100000 * 1e-4, 0.0, 0.0));
    // Raw counts × 1e-6 rad, i.e. 84.40°, −0.50°, 1.20° to the 1e-6 rad quantum.
    EXPECT_EQ(s.heading_rad, 1473058 * 1e-6);
    EXPECT_EQ(s.pitch_rad, -8727 * 1e-6);
    EXPECT_EQ(s.roll_rad, 20944 * 1e-6);
    EXPECT_NEAR(s.heading_rad, 84.40 * kDeg, 0.5e-6);
    EXPECT_NEAR(s.pitch_rad, -0.50 * kDeg, 0.5e-6);
    EXPECT_NEAR(s.roll_rad, 1.20 * kDeg, 0.5e-6);
    EXPECT_EQ(s.accel_frd_mps2, Eigen::Vector3d(5000 * 1e-4, 0.0, -98100 * 1e-4));
    EXPECT_NEAR(s.accel_frd_mps2.z(), -9.81, 1e-12);
    EXPECT_EQ(s.rate_frd_radps, Eigen::Vector3d::Zero());
    EXPECT_EQ(s.satellites, 12);
    EXPECT_EQ(s.quality, FixQuality::Differential);  // position mode 4
    EXPECT_EQ(dec.channel0().gps_minutes, 24'598'200);
    EXPECT_EQ(dec.counters().messages_ok, 1U);
    EXPECT_EQ(dec.counters().samples, 1U);
}

TEST(NcomVector, encoder_produces_exactly_its_bytes) {
    NcomEncoder enc;
    const auto bytes = enc.encode(vector_sample());
    EXPECT_EQ(std::vector<std::uint8_t>(bytes.begin(), bytes.end()), kVector);
}

TEST(NcomVector, i24_fields_are_twos_complement_with_0x800000_invalid) {
    std::uint8_t b[3];
    write_i24(b, -98100);
    EXPECT_EQ(b[0], 0xCC);
    EXPECT_EQ(b[1], 0x80);
    EXPECT_EQ(b[2], 0xFE);
    EXPECT_EQ(read_i24(b), -98100);
    const std::uint8_t inv[3] = {0x00, 0x00, 0x80};
    EXPECT_EQ(read_i24(inv), kInvalidI24);
    const std::uint8_t max[3] = {0xFF, 0xFF, 0x7F};
    EXPECT_EQ(read_i24(max), kMaxI24);
    EXPECT_EQ(quantise_i24(1e9, 1e-4), kMaxI24);  // clamped, never the invalid marker
    EXPECT_EQ(quantise_i24(-1e9, 1e-4), -kMaxI24);
    EXPECT_EQ(quantise_i24(std::nan(""), 1e-4), kInvalidI24);
}

}  // namespace
