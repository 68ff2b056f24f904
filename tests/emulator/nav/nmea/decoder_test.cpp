// SPDX-License-Identifier: Apache-2.0
// NmeaDecoder: the NavSample convention mappings (closed-form cases), the date/time logic, and
// the incremental framing under random splits, garbage and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mirage/nmea/nmea_decoder.hpp"
#include "mirage/nmea/sentence.hpp"
#include "nmea_test_util.hpp"

namespace mirage::nmea {
namespace {

using nav::FixQuality;
using nav::NavSample;
using test::decode_all;
using test::decode_split;
using test::deg;
using test::gps_ns;
using test::rad;

// A date-setting RMC (2014-02-19 20:41:32 UTC, 10 kn due east) to start streams with.
const std::string kDateRmc =
    frame_sentence("GPRMC,204132.00,A,4205.733476,N,08802.041110,W,10.0,90.0,190214,,,D");

std::string f(const std::string& body) { return frame_sentence(body); }

TEST(NmeaDecoder, rmc_time_is_utc_plus_leap_seconds_and_velocity_is_ned) {
    NmeaDecoder d;
    EXPECT_FALSE(d.has_date());
    const auto out = decode_all(d, kDateRmc);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_TRUE(d.has_date());
    const NavSample& s = out[0];
    EXPECT_EQ(s.fields, NavSample::kTime | NavSample::kVelocity);
    // 2014-02-19T20:41:32Z = Unix 1392842492; GPS − UTC = 16 s in 2014.
    EXPECT_EQ(s.t.time_since_epoch().count(), (1392842492LL - 315964800LL + 16) * 1'000'000'000LL);
    EXPECT_NEAR(s.velocity_ned_mps.x(), 0.0, 1e-12);
    EXPECT_NEAR(s.velocity_ned_mps.y(), 10.0 * 1852.0 / 3600.0, 1e-12);  // east
    EXPECT_EQ(s.velocity_ned_mps.z(), 0.0);                              // no vertical speed
    EXPECT_EQ(s.quality, FixQuality::Differential);                      // FAA mode D
}

TEST(NmeaDecoder, gga_height_is_msl_plus_geoid_separation) {
    NmeaDecoder d;
    const auto out = decode_all(
        d, kDateRmc +
               f("GPGGA,204132.10,4205.733715,N,08802.040978,W,4,12,0.8,221.921,M,-33.5,M,,") +
               f("GPGGA,204132.20,3345.500000,S,15112.000000,E,5,07,0.8,221.912,M,,,3,0138"));
    ASSERT_EQ(out.size(), 3u);
    const NavSample& a = out[1];
    EXPECT_EQ(a.fields, NavSample::kTime | NavSample::kPosition);
    EXPECT_NEAR(a.height_m, 221.921 - 33.5, 1e-9);  // ellipsoidal = MSL + separation
    EXPECT_NEAR(a.lat_deg, 42.0 + 5.733715 / 60.0, 1e-12);
    EXPECT_NEAR(a.lon_deg, -(88.0 + 2.040978 / 60.0), 1e-12);  // W is negative
    EXPECT_EQ(a.quality, FixQuality::RtkFixed);
    EXPECT_EQ(a.satellites, 12);
    EXPECT_EQ(a.t.time_since_epoch().count() - out[0].t.time_since_epoch().count(), 100'000'000);
    const NavSample& b = out[2];
    EXPECT_EQ(b.fields, NavSample::kTime | NavSample::kPosition | NavSample::kHeightIsMsl);
    EXPECT_NEAR(b.height_m, 221.912, 1e-9);
    EXPECT_NEAR(b.lat_deg, -(33.0 + 45.5 / 60.0), 1e-12);  // S is negative
    EXPECT_NEAR(b.lon_deg, 151.2, 1e-12);
    EXPECT_EQ(b.quality, FixQuality::RtkFloat);
}

TEST(NmeaDecoder, gga_quality_codes_map_to_fix_quality) {
    const FixQuality want[] = {
        FixQuality::None,          FixQuality::Autonomous, FixQuality::Differential,
        FixQuality::Differential,  FixQuality::RtkFixed,   FixQuality::RtkFloat,
        FixQuality::DeadReckoning, FixQuality::Unknown,    FixQuality::Simulated};
    for (int q = 0; q <= 8; ++q) {
        NmeaDecoder d;
        const auto out = decode_all(d, kDateRmc + f("GPGGA,204133,4205.7,N,08802.0,W," +
                                                    std::to_string(q) + ",05,1,10,M,0,M,,"));
        ASSERT_EQ(out.size(), 2u);
        EXPECT_EQ(out[1].quality, want[q]) << q;
        EXPECT_EQ(out[1].has(NavSample::kPosition), q != 0) << q;  // 0: fix not valid
    }
    NmeaDecoder d;
    decode_all(d, kDateRmc + f("GPGGA,204133,4205.7,N,08802.0,W,9,05,1,10,M,0,M,,"));
    EXPECT_EQ(d.counters().invalid_field, 1u);
}

TEST(NmeaDecoder, heading_350_and_yaw_minus_10_are_the_same_heading) {
    NmeaDecoder d;
    const auto out =
        decode_all(d, kDateRmc + f("HEHDT,350.00,T") +
                          f("PTNL,AVR,204133.0,-10.0000,Yaw,+2.5000,Tilt,,,1.5,3,1.2,9") +
                          f("GPHDT,360.00,T"));
    ASSERT_EQ(out.size(), 4u);
    EXPECT_EQ(out[1].fields, NavSample::kHeading);  // HDT carries no time: no kTime
    EXPECT_EQ(out[1].t, out[0].t);                  // ... t is the latest timed sentence's
    EXPECT_NEAR(out[1].heading_rad, rad(350.0), 1e-12);
    EXPECT_EQ(out[2].fields, NavSample::kTime | NavSample::kHeading);
    EXPECT_NEAR(out[2].heading_rad, rad(350.0), 1e-12);
    EXPECT_NEAR(out[2].pitch_rad, rad(2.5), 1e-12);  // tilt
    EXPECT_EQ(out[2].quality, FixQuality::RtkFixed);
    EXPECT_EQ(out[2].satellites, 9);
    EXPECT_EQ(out[3].heading_rad, 0.0);  // 360 wraps into [0, 2π)
}

// OxTS roll positive right side down, pitch positive nose up = NavSample's convention.
TEST(NmeaDecoder, pashr_roll_and_pitch_keep_their_signs) {
    NmeaDecoder d;
    const auto out = decode_all(
        d, kDateRmc + f("PASHR,204132.040,010.99,T,+05.00,-03.00,-00.84,0.151,0.088,0.569,1,0") +
               f("PASHR,204132.080,359.99,T,-45.50,+10.25,+00.00,0.151,0.088,0.569,1,0"));
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(out[1].fields, NavSample::kTime | NavSample::kAttitude);
    EXPECT_NEAR(out[1].roll_rad, rad(5.0), 1e-12);
    EXPECT_NEAR(out[1].pitch_rad, rad(-3.0), 1e-12);
    EXPECT_NEAR(out[1].heading_rad, rad(10.99), 1e-12);
    EXPECT_EQ(out[1].t.time_since_epoch().count() - out[0].t.time_since_epoch().count(),
              40'000'000);
    EXPECT_NEAR(out[2].roll_rad, rad(-45.5), 1e-12);
    EXPECT_NEAR(out[2].pitch_rad, rad(10.25), 1e-12);
    EXPECT_NEAR(out[2].heading_rad, rad(359.99), 1e-12);
}

TEST(NmeaDecoder, vtg_both_forms_give_ned_velocity) {
    NmeaDecoder d;
    const auto out =
        decode_all(d, kDateRmc + f("GPVTG,180.0,T,,M,2.0,N,3.704,K,A") +
                          f("GPVTG,270.0,T,,M,,N,3.704,K,A") + f("GPVTG,054.7,034.4,005.5,010.2"));
    ASSERT_EQ(out.size(), 4u);
    const double kn = 1852.0 / 3600.0;
    EXPECT_EQ(out[1].fields, NavSample::kVelocity);
    EXPECT_NEAR(out[1].velocity_ned_mps.x(), -2.0 * kn, 1e-12);  // due south
    EXPECT_NEAR(out[1].velocity_ned_mps.y(), 0.0, 1e-12);
    EXPECT_NEAR(out[2].velocity_ned_mps.y(), -2.0 * kn, 1e-12);  // km/h only, due west
    EXPECT_NEAR(out[3].velocity_ned_mps.norm(), 5.5 * kn, 1e-12);
    EXPECT_NEAR(deg(std::atan2(out[3].velocity_ned_mps.y(), out[3].velocity_ned_mps.x())), 54.7,
                1e-9);
}

TEST(NmeaDecoder, nothing_is_emitted_before_a_date_and_the_hint_supplies_one) {
    const std::string gga = f("GPGGA,204132.10,4205.733715,N,08802.040978,W,2,08,1.0,221.9,M,,,,");
    NmeaDecoder d;
    EXPECT_TRUE(decode_all(d, gga + f("GPHDT,25.50,T")).empty());
    EXPECT_FALSE(d.has_date());
    EXPECT_EQ(d.nmea_counters().before_date, 2u);
    EXPECT_EQ(d.counters().messages_ok, 2u);
    EXPECT_EQ(d.counters().samples, 0u);

    NmeaDecoder h;
    h.set_date_hint(Date{2014, 2, 19});
    EXPECT_TRUE(h.has_date());
    const auto out = decode_all(h, gga);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].t.time_since_epoch().count(), gps_ns("2014-02-19T20:41:32.1Z"));
    // A date from the stream overrides the hint; a later hint is ignored.
    decode_all(h, f("GPZDA,000001.000,01,03,2015,,"));
    h.set_date_hint(Date{2000, 1, 1});
    const auto later = decode_all(h, f("GPGGA,000002,4205.7,N,08802.0,W,1,05,1,10,M,0,M,,"));
    EXPECT_EQ(later.at(0).t.time_since_epoch().count(), gps_ns("2015-03-01T00:00:02Z"));
}

TEST(NmeaDecoder, midnight_rollover_advances_the_kept_date) {
    NmeaDecoder d;
    const auto out = decode_all(
        d, f("GPZDA,235959.50,31,12,2014,00,00") +
               f("GPGGA,235959.90,4205.7,N,08802.0,W,1,05,1,10,M,0,M,,") +
               f("GPGGA,000000.30,4205.7,N,08802.0,W,1,05,1,10,M,0,M,,") +
               f("GPGGA,235959.95,4205.7,N,08802.0,W,1,05,1,10,M,0,M,,") +  // late, previous day
               f("GPGGA,000000.40,4205.7,N,08802.0,W,1,05,1,10,M,0,M,,"));
    ASSERT_EQ(out.size(), 5u);
    EXPECT_EQ(out[1].t.time_since_epoch().count(), gps_ns("2014-12-31T23:59:59.9Z"));
    EXPECT_EQ(out[2].t.time_since_epoch().count(), gps_ns("2015-01-01T00:00:00.3Z"));
    EXPECT_EQ(out[3].t.time_since_epoch().count(), gps_ns("2014-12-31T23:59:59.95Z"));
    EXPECT_EQ(out[4].t.time_since_epoch().count(), gps_ns("2015-01-01T00:00:00.4Z"));
}

TEST(NmeaDecoder, leap_second_2359_60_lands_on_the_inserted_second) {
    NmeaDecoder d;
    const auto out = decode_all(
        d, f("GPZDA,235960.50,31,12,2016,00,00") + f("GPZDA,000000.00,01,01,2017,00,00"));
    ASSERT_EQ(out.size(), 2u);
    // GPS − UTC became 18 s at 2017-01-01T00:00:00Z = Unix 1483228800.
    const std::int64_t midnight_gps_s = 1483228800LL - 315964800LL + 18;
    EXPECT_EQ(out[1].t.time_since_epoch().count(), midnight_gps_s * 1'000'000'000LL);
    EXPECT_EQ(out[0].t.time_since_epoch().count(), midnight_gps_s * 1'000'000'000LL - 500'000'000);
}

// A stream with every sentence type, decoded in one piece and in random pieces.
std::string mixed_stream() {
    std::string s = kDateRmc;
    for (int i = 0; i < 20; ++i) {
        const std::string t = "2041" + std::to_string(33 + i / 10) + "." + std::to_string(i % 10);
        s += f("GPGGA," + t + "0,4205.73" + std::to_string(i % 10) +
               ",N,08802.04,W,2,08,1.0,221.9,M,-33.1,M,,");
        s += f("PASHR," + t + "00,0" + std::to_string(10 + i) +
               ".50,T,+00.39,-00.79,-00.84,0.151,0.075,0.555,1,0");
        s += f("GPHDT," + std::to_string(10 + i) + ".5,T");
        s += f("GPVTG,054.7,T,,M,005.5,N,010.2,K,D");
        s += f("PTNL,AVR," + t + ",+149.4688,Yaw,+0.0134,Tilt,,,60.191,3,2.5,6");
    }
    s += f("GPZDA,204136.000,19,02,2014,,");
    return s;
}

TEST(NmeaDecoder, random_splits_give_identical_samples) {
    const std::string stream = mixed_stream();
    NmeaDecoder whole;
    const auto ref = decode_all(whole, stream);
    ASSERT_EQ(ref.size(), 102u);
    EXPECT_EQ(whole.counters().rejected(), 0u);
    for (std::uint32_t seed = 1; seed <= 30; ++seed) {
        NmeaDecoder d;
        const auto got = decode_split(d, stream, seed, seed % 3 == 0 ? 1 : 37);
        ASSERT_EQ(got.size(), ref.size()) << seed;
        for (std::size_t i = 0; i < ref.size(); ++i) {
            EXPECT_TRUE(test::same_sample(got[i], ref[i])) << "seed " << seed << " sample " << i;
        }
        EXPECT_EQ(d.counters().messages_ok, whole.counters().messages_ok);
    }
}

TEST(NmeaDecoder, garbage_between_sentences_is_skipped_and_counted) {
    const std::string clean = mixed_stream();
    NmeaDecoder ref_d;
    const auto ref = decode_all(ref_d, clean);
    // Insert binary/ASCII junk (no `$`, CR or LF) before every `$`.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> len(0, 12), byte(0, 255);
    std::string dirty;
    std::uint64_t junk = 0;
    for (char c : clean) {
        if (c == '$') {
            const int n = len(rng);
            for (int i = 0; i < n; ++i) {
                char g = static_cast<char>(byte(rng));
                if (g == '$' || g == '\r' || g == '\n') g = '#';
                dirty += g;
                ++junk;
            }
        }
        dirty += c;
    }
    NmeaDecoder d;
    const auto got = decode_split(d, dirty, 3, 50);
    ASSERT_EQ(got.size(), ref.size());
    for (std::size_t i = 0; i < ref.size(); ++i) EXPECT_TRUE(test::same_sample(got[i], ref[i]));
    EXPECT_EQ(d.counters().garbage_bytes, junk);
    EXPECT_EQ(d.counters().rejected(), 0u);
}

TEST(NmeaDecoder, truncated_badsum_overlong_and_invalid_sentences_are_counted_not_applied) {
    NmeaDecoder d;
    std::string s = kDateRmc;
    const std::string good_gga = f("GPGGA,204132.50,4205.7,N,08802.0,W,1,05,1,10,M,0,M,,");
    s += good_gga.substr(0, 30);  // cut short, the next `$` arrives
    s += f("GPHDT,11.0,T");
    s += good_gga.substr(0, 30) + "\r\n";  // cut short, then a line end: no `*hh`
    std::string bad = f("GPZDA,000000.00,01,01,2020,00,00");  // would change the date
    bad[bad.size() - 3] = bad[bad.size() - 3] == '0' ? '1' : '0';
    s += bad;
    s += "$GPGGA," + std::string(130, '1') + "*00\r\n";                 // over-long line
    s += f("GPGGA,204132.50,9100.0,N,08802.0,W,1,05,1,10,M,0,M,,");     // lat > 90
    s += f("GPGGA,204132.50,4260.0,N,08802.0,W,1,05,1,10,M,0,M,,");     // minutes >= 60
    s += f("GPRMC,204133.00,A,4205.7,N,08802.0,W,1.0,2.0,191314,,,D");  // month 13
    s += f("GPGGA,204132.50,4205.7,N,08802.0,W,1,05,1,nan,M,0,M,,");    // NaN text
    s += f("PASHR,204132.040,inf,T,+00.41,-00.75,-00.84,0.151,0.088,0.569,1,0");
    s += f("GPHDT,-5.0,T");                                                      // out of [0, 360]
    s += f("GPGSV,3,1,11,03,03,111,00,04,15,270,00,06,01,010,00,13,06,292,00");  // unsupported
    s += f("PASHR,POS,0,06,123519.00,4807.03800,N,01131.00000,E,+00545.40,,000.00");
    s += f("GPHDT,12.0,T");
    const auto out = decode_all(d, s);
    ASSERT_EQ(out.size(), 3u);  // RMC and the two good HDTs
    EXPECT_NEAR(out[1].heading_rad, rad(11.0), 1e-12);
    EXPECT_NEAR(out[2].heading_rad, rad(12.0), 1e-12);
    EXPECT_EQ(out[2].t, out[0].t);  // no invalid sentence moved the time or the date
    const auto& c = d.counters();
    EXPECT_EQ(c.truncated, 3u);
    EXPECT_EQ(c.bad_checksum, 1u);
    EXPECT_EQ(c.invalid_field, 6u);
    EXPECT_EQ(c.unsupported, 2u);
    EXPECT_EQ(c.messages_ok, 3u);
    EXPECT_EQ(c.samples, 3u);
    EXPECT_EQ(c.rejected(), 10u);
}

TEST(NmeaDecoder, lf_only_line_endings_and_empty_fields_mean_no_data) {
    NmeaDecoder d;
    std::string s = kDateRmc;
    s += "$GPHDT,1.5,T*" + frame_sentence("GPHDT,1.5,T").substr(13, 2) + "\n";
    s += f("GPGGA,204133.00,,,,,0,00,,,M,,M,,");  // no fix: time and quality only
    s += f("GPHDT,,T");                           // empty heading: nothing to emit
    const auto out = decode_all(d, s);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_NEAR(out[1].heading_rad, rad(1.5), 1e-12);
    EXPECT_EQ(out[2].fields, NavSample::kTime);
    EXPECT_EQ(out[2].quality, FixQuality::None);
    EXPECT_EQ(d.nmea_counters().no_data, 1u);
    EXPECT_EQ(d.counters().rejected(), 0u);
}

}  // namespace
}  // namespace mirage::nmea
