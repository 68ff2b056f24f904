// SPDX-License-Identifier: Apache-2.0
// Encoder -> decoder round trips of random NavSamples, within the printed precision.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "mirage/nmea/nmea_decoder.hpp"
#include "mirage/nmea/nmea_encoder.hpp"
#include "nmea_test_util.hpp"

namespace mirage::nmea {
namespace {

using nav::FixQuality;
using nav::NavSample;
using test::deg;
using test::kPi;

constexpr double kMPerDegLat = 111'320.0;  // upper bound of a degree of latitude, m
constexpr double kKnot = 1852.0 / 3600.0;

NavSample random_sample(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const FixQuality qualities[] = {FixQuality::Autonomous,    FixQuality::Differential,
                                    FixQuality::RtkFixed,      FixQuality::RtkFloat,
                                    FixQuality::DeadReckoning, FixQuality::Simulated};
    NavSample s;
    s.fields =
        NavSample::kTime | NavSample::kPosition | NavSample::kVelocity | NavSample::kAttitude;
    // 2000-01-01 .. 2030-01-01 in GPS ns, at an arbitrary ns.
    const std::int64_t t0 = 630'720'013LL * 1'000'000'000LL;
    s.t = core::GpsTime{core::Nanos{t0 + static_cast<std::int64_t>(u(rng) * 9.46e17)}};
    s.lat_deg = -89.99 + 179.98 * u(rng);
    s.lon_deg = -180.0 + 359.999999 * u(rng);
    s.height_m = -400.0 + 9000.0 * u(rng);
    s.velocity_ned_mps = {-60.0 + 120.0 * u(rng), -60.0 + 120.0 * u(rng), 0.0};
    s.heading_rad = 2.0 * kPi * u(rng);
    s.roll_rad = (-0.9 + 1.8 * u(rng)) * kPi / 2;
    s.pitch_rad = (-0.9 + 1.8 * u(rng)) * kPi / 4;
    s.quality = qualities[rng() % 6];
    s.satellites = static_cast<std::uint8_t>(rng() % 40);
    return s;
}

// Smallest angle between two headings, degrees.
double heading_diff_deg(double a_rad, double b_rad) {
    double d = std::fmod(std::fabs(a_rad - b_rad), 2.0 * kPi);
    return deg(std::min(d, 2.0 * kPi - d));
}

TEST(NmeaRoundTrip, random_samples_survive_encode_then_decode) {
    std::mt19937_64 rng(42);
    double worst_pos_m = 0, worst_h_m = 0, worst_v = 0, worst_att_deg = 0;
    std::int64_t worst_t_ns = 0;
    for (int i = 0; i < 500; ++i) {
        const NavSample in = random_sample(rng);
        EncodeOptions o;
        o.geoid_separation_m = -100.0 + 0.2 * static_cast<double>(rng() % 1000);
        const std::string text =
            encode_epoch(in, kZda | kRmc | kGga | kVtg | kHdt | kPashr | kPtnlAvr, o);
        NmeaDecoder d;
        const auto out = test::decode_all(d, text);
        ASSERT_EQ(out.size(), 7u) << text;
        ASSERT_EQ(d.counters().rejected(), 0u) << text;
        // Order: ZDA, RMC, GGA, VTG, HDT, PASHR, PTNL,AVR.
        const NavSample &zda = out[0], &rmc = out[1], &gga = out[2], &vtg = out[3], &hdt = out[4],
                        &pashr = out[5], &avr = out[6];
        const std::int64_t tin = in.t.time_since_epoch().count();
        auto dt = [&](const NavSample& s) {
            return std::llabs(s.t.time_since_epoch().count() - tin);
        };
        EXPECT_LE(dt(zda), 5'000'000);  // hhmmss.ss: ±5 ms
        EXPECT_LE(dt(rmc), 5'000'000);
        EXPECT_LE(dt(gga), 5'000'000);
        EXPECT_LE(dt(pashr), 500'000);   // hhmmss.sss
        EXPECT_LE(dt(avr), 50'000'000);  // hhmmss.s
        worst_t_ns = std::max<std::int64_t>({worst_t_ns, dt(zda), dt(gga)});

        ASSERT_TRUE(gga.has(NavSample::kPosition));
        EXPECT_FALSE(gga.has(NavSample::kHeightIsMsl));
        const double dn = (gga.lat_deg - in.lat_deg) * kMPerDegLat;
        const double de = (gga.lon_deg - in.lon_deg) * kMPerDegLat;
        EXPECT_LT(std::fabs(dn), 1e-3);  // < 1 mm, even in longitude at the equator
        EXPECT_LT(std::fabs(de), 1e-3);
        EXPECT_LE(std::fabs(gga.height_m - in.height_m), 1.0e-3 + 1e-9);
        EXPECT_EQ(gga.quality, in.quality);
        EXPECT_EQ(gga.satellites, in.satellites);
        worst_pos_m = std::max({worst_pos_m, std::fabs(dn), std::fabs(de)});
        worst_h_m = std::max(worst_h_m, std::fabs(gga.height_m - in.height_m));

        // Speed printed to 0.001 kn, track to 0.001°.
        const double speed = in.velocity_ned_mps.head<2>().norm();
        const double tol_v = 0.0005 * kKnot + speed * 0.0005 * kPi / 180.0 + 1e-9;
        for (const NavSample* v : {&rmc, &vtg}) {
            ASSERT_TRUE(v->has(NavSample::kVelocity));
            EXPECT_LE((v->velocity_ned_mps - in.velocity_ned_mps).norm(), 2 * tol_v);
            worst_v = std::max(worst_v, (v->velocity_ned_mps - in.velocity_ned_mps).norm());
        }
        EXPECT_EQ(rmc.quality, in.quality);  // through the FAA mode letter

        EXPECT_LE(heading_diff_deg(hdt.heading_rad, in.heading_rad), 0.005 + 1e-9);
        EXPECT_LE(heading_diff_deg(pashr.heading_rad, in.heading_rad), 0.005 + 1e-9);
        EXPECT_LE(std::fabs(deg(pashr.roll_rad - in.roll_rad)), 0.005 + 1e-9);
        EXPECT_LE(std::fabs(deg(pashr.pitch_rad - in.pitch_rad)), 0.005 + 1e-9);
        EXPECT_LE(heading_diff_deg(avr.heading_rad, in.heading_rad), 0.00005 + 1e-9);
        EXPECT_LE(std::fabs(deg(avr.pitch_rad - in.pitch_rad)), 0.00005 + 1e-9);
        worst_att_deg = std::max(worst_att_deg, std::fabs(deg(pashr.roll_rad - in.roll_rad)));
    }
    std::printf(
        "round trip worst: position %.3g mm, height %.3g mm, velocity %.3g m/s, "
        "roll %.3g deg, time %.3g ms\n",
        worst_pos_m * 1e3, worst_h_m * 1e3, worst_v, worst_att_deg,
        static_cast<double>(worst_t_ns) * 1e-6);
}

TEST(NmeaRoundTrip, minutes_rounding_to_60_carries_into_degrees) {
    NavSample s;
    s.fields = NavSample::kTime | NavSample::kPosition;
    s.t = core::GpsTime{core::Nanos{test::gps_ns("2024-05-01T12:00:00Z")}};
    s.lat_deg = -(10.0 - 1e-12);  // 9° 59.99999999994'
    s.lon_deg = 179.0 + 59.999999999 / 60.0;
    s.height_m = 5.0;
    s.quality = FixQuality::Autonomous;
    const std::string gga = encode_gga(s);
    EXPECT_NE(gga.find(",1000.0000000,S,18000.0000000,E,"), std::string::npos) << gga;
}

TEST(NmeaRoundTrip, msl_only_samples_leave_the_separation_empty) {
    NavSample s;
    s.fields = NavSample::kTime | NavSample::kPosition | NavSample::kHeightIsMsl;
    s.t = core::GpsTime{core::Nanos{test::gps_ns("2024-05-01T12:00:00Z")}};
    s.lat_deg = 1.5;
    s.lon_deg = -2.5;
    s.height_m = 123.456;
    s.quality = FixQuality::RtkFixed;
    NmeaDecoder d;
    d.set_date_hint(Date{2024, 5, 1});
    const auto out = test::decode_all(d, encode_gga(s));
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].fields, s.fields);
    EXPECT_DOUBLE_EQ(out[0].height_m, 123.456);
    EXPECT_EQ(out[0].t, s.t);
}

}  // namespace
}  // namespace mirage::nmea
