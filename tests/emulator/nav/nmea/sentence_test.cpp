// SPDX-License-Identifier: Apache-2.0
// Sentence layer and typed parsers against the test vectors of docs/nav-protocols.md §1, and the
// encoder reproducing them byte for byte (hence their checksums).
#include "mirage/nmea/sentence.hpp"

#include <gtest/gtest.h>

#include <string>

#include "mirage/nmea/nmea_encoder.hpp"
#include "mirage/nmea/sentences.hpp"
#include "nmea_test_util.hpp"

namespace mirage::nmea {
namespace {

using nav::FixQuality;
using nav::NavSample;
using test::gps_ns;
using test::rad;

const std::string kGgaVector = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47";
const std::string kRmcVector =
    "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A";
const std::string kHdtVector = "$GPHDT,274.07,T*03";
const std::string kZdaVector = "$GPZDA,160012.71,11,03,2004,-1,00*7D";
const std::string kPashrVector =
    "$PASHR,085335.000,224.19,T,-01.26,+00.83,+00.00,0.101,0.113,0.267,1,0*06";
const std::string kAvrVector = "$PTNL,AVR,181059.6,+149.4688,Yaw,+0.0134,Tilt,,,60.191,3,2.5,6*00";

Sentence framed(const std::string& line) {
    Sentence s;
    EXPECT_EQ(parse_sentence(line, s), FrameStatus::Ok) << line;
    return s;
}

TEST(NmeaSentence, checksum_is_xor_between_dollar_and_star_for_all_six_vectors) {
    for (const std::string& v :
         {kGgaVector, kRmcVector, kHdtVector, kZdaVector, kPashrVector, kAvrVector}) {
        const std::size_t star = v.find('*');
        const std::string body = v.substr(1, star - 1);
        EXPECT_EQ(checksum(body), std::stoi(v.substr(star + 1), nullptr, 16)) << v;
        EXPECT_EQ(frame_sentence(body), v + "\r\n");
    }
    EXPECT_EQ(checksum(""), 0);
    EXPECT_EQ(checksum("PTNL,AVR,181059.6,+149.4688,Yaw,+0.0134,Tilt,,,60.191,3,2.5,6"), 0x00);
}

TEST(NmeaSentence, tag_type_is_independent_of_talker) {
    for (const char* talker : {"GP", "GN", "GL", "GA", "GB", "IN", "HE"}) {
        const std::string line = frame_sentence(std::string(talker) + "HDT,12.5,T");
        const Sentence s = framed(line);
        EXPECT_EQ(s.type, SentenceType::Hdt);
        EXPECT_EQ(s.talker, talker);
        EXPECT_EQ(s.count, 2u);
        EXPECT_EQ(s.at(0), "12.5");
        EXPECT_EQ(s.at(5), "");  // past the end: no data
    }
    EXPECT_EQ(framed(kPashrVector).type, SentenceType::Pashr);
    EXPECT_EQ(framed(kAvrVector).type, SentenceType::PtnlAvr);
    EXPECT_EQ(framed(frame_sentence("GPGSV,1,1,00")).type, SentenceType::Unknown);
}

TEST(NmeaSentence, framing_errors_are_classified) {
    Sentence s;
    EXPECT_EQ(parse_sentence("$GPHDT,274.07,T*03\r\n", s), FrameStatus::Ok);
    EXPECT_EQ(parse_sentence("$GPHDT,274.07,T*03\n", s), FrameStatus::Ok);
    EXPECT_EQ(parse_sentence("GPHDT,274.07,T*03", s), FrameStatus::NoSync);
    EXPECT_EQ(parse_sentence("$GPHDT,274.07,T*04", s), FrameStatus::BadChecksum);
    EXPECT_EQ(parse_sentence("$GPHDT,274.07,T*0G", s), FrameStatus::BadChecksum);
    EXPECT_EQ(parse_sentence("$GPHDT,274.07,T", s), FrameStatus::Truncated);
    EXPECT_EQ(parse_sentence("$GPHDT,274.07,T*0", s), FrameStatus::Truncated);
    EXPECT_EQ(parse_sentence("$GPHDT,274.07,T*03x", s), FrameStatus::Truncated);
    const std::string lower =
        "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6a";
    EXPECT_EQ(parse_sentence(lower, s), FrameStatus::Ok);
    EXPECT_EQ(parse_sentence(frame_sentence("gphdt,1,T"), s), FrameStatus::BadTag);
    EXPECT_EQ(parse_sentence(frame_sentence("GPHDT,1\x01,T"), s), FrameStatus::BadChar);
    // 120 bytes with CR LF is the limit.
    const std::string body118 = "GPXXX," + std::string(118 - 1 - 6 - 3, '1');
    EXPECT_EQ(frame_sentence(body118).size(), 120u);
    EXPECT_EQ(parse_sentence(frame_sentence(body118), s), FrameStatus::Ok);
    EXPECT_EQ(parse_sentence(frame_sentence(body118 + "1"), s), FrameStatus::TooLong);
}

TEST(NmeaSentence, gga_vector_decodes_every_field) {
    Gga g;
    ASSERT_EQ(parse_gga(framed(kGgaVector), g), ParseStatus::Ok);
    ASSERT_TRUE(g.time);
    EXPECT_EQ(g.time->ns_of_day(), (12 * 3600 + 35 * 60 + 19) * 1'000'000'000LL);
    EXPECT_NEAR(*g.lat_deg, 48.0 + 7.038 / 60.0, 1e-12);
    EXPECT_NEAR(*g.lon_deg, 11.0 + 31.0 / 60.0, 1e-12);
    EXPECT_EQ(g.quality, 1);
    EXPECT_EQ(*g.satellites, 8);
    EXPECT_DOUBLE_EQ(*g.hdop, 0.9);
    EXPECT_DOUBLE_EQ(*g.altitude_msl_m, 545.4);
    EXPECT_DOUBLE_EQ(*g.geoid_separation_m, 46.9);
}

TEST(NmeaSentence, rmc_vector_decodes_every_field) {
    Rmc r;
    ASSERT_EQ(parse_rmc(framed(kRmcVector), r), ParseStatus::Ok);
    EXPECT_TRUE(r.valid);
    EXPECT_NEAR(*r.lat_deg, 48.1173, 1e-12);
    EXPECT_DOUBLE_EQ(*r.speed_knots, 22.4);
    EXPECT_DOUBLE_EQ(*r.track_deg, 84.4);
    EXPECT_EQ(*r.date, (Date{1994, 3, 23}));
    EXPECT_DOUBLE_EQ(*r.magnetic_variation_deg, -3.1);  // west is negative
    EXPECT_EQ(r.mode, '\0');                            // NMEA 2.0: no FAA mode field
}

TEST(NmeaSentence, hdt_zda_pashr_avr_vectors_decode_every_field) {
    Hdt h;
    ASSERT_EQ(parse_hdt(framed(kHdtVector), h), ParseStatus::Ok);
    EXPECT_DOUBLE_EQ(*h.heading_deg, 274.07);

    Zda z;
    ASSERT_EQ(parse_zda(framed(kZdaVector), z), ParseStatus::Ok);
    EXPECT_EQ(z.time->ns_of_day(), (16 * 3600 + 12) * 1'000'000'000LL + 710'000'000);
    EXPECT_EQ(*z.date, (Date{2004, 3, 11}));
    EXPECT_EQ(*z.zone_hours, -1);
    EXPECT_EQ(*z.zone_minutes, 0);

    // A year whose ns since 1970 overflow int64 is an invalid field (fuzz_nmea), 2200 is not.
    Zda far;
    EXPECT_NE(parse_zda(framed(frame_sentence("GPZDA,160012.71,11,03,2420,-1,00")), far),
              ParseStatus::Ok);
    EXPECT_FALSE(far.date);
    ASSERT_EQ(parse_zda(framed(frame_sentence("GPZDA,160012.71,31,12,2200,-1,00")), far),
              ParseStatus::Ok);
    EXPECT_EQ(*far.date, (Date{2200, 12, 31}));

    Pashr p;
    ASSERT_EQ(parse_pashr(framed(kPashrVector), p), ParseStatus::Ok);
    EXPECT_EQ(p.time->ns_of_day(), (8 * 3600 + 53 * 60 + 35) * 1'000'000'000LL);
    EXPECT_DOUBLE_EQ(*p.heading_deg, 224.19);
    EXPECT_DOUBLE_EQ(*p.roll_deg, -1.26);
    EXPECT_DOUBLE_EQ(*p.pitch_deg, 0.83);
    EXPECT_DOUBLE_EQ(*p.heave_m, 0.0);
    EXPECT_DOUBLE_EQ(*p.roll_sigma_deg, 0.101);
    EXPECT_DOUBLE_EQ(*p.pitch_sigma_deg, 0.113);
    EXPECT_DOUBLE_EQ(*p.heading_sigma_deg, 0.267);
    EXPECT_EQ(*p.aiding_status, 1);
    EXPECT_EQ(*p.imu_status, 0);

    PtnlAvr a;
    ASSERT_EQ(parse_ptnl_avr(framed(kAvrVector), a), ParseStatus::Ok);
    EXPECT_EQ(a.time->ns_of_day(), (18 * 3600 + 10 * 60 + 59) * 1'000'000'000LL + 600'000'000);
    EXPECT_DOUBLE_EQ(*a.yaw_deg, 149.4688);
    EXPECT_DOUBLE_EQ(*a.tilt_deg, 0.0134);
    EXPECT_FALSE(a.roll_deg);
    EXPECT_DOUBLE_EQ(*a.range_m, 60.191);
    EXPECT_EQ(a.quality, 3);
    EXPECT_DOUBLE_EQ(*a.pdop, 2.5);
    EXPECT_EQ(*a.satellites, 6);
}

TEST(NmeaSentence, ashtech_pashr_pos_is_unsupported) {
    Pashr p;
    const Sentence s = framed(frame_sentence(
        "PASHR,POS,0,06,123519.00,4807.03800,N,01131.00000,E,+00545.40,,000.00,000.00,+000.00,"
        "02.0,,,,XXXX"));
    EXPECT_EQ(s.type, SentenceType::Pashr);
    EXPECT_EQ(parse_pashr(s, p), ParseStatus::Unsupported);
}

// The encoder, configured like the receivers that produced the vectors, reproduces each one.
TEST(NmeaEncoder, reproduces_the_six_vectors_and_their_checksums) {
    EncodeOptions old;  // a 1990s receiver: integer seconds, 3 minute decimals, NMEA 2.0 RMC
    old.time_decimals = 0;
    old.minute_decimals = 3;
    old.height_decimals = 1;
    old.geoid_separation_m = 46.9;
    old.hdop = 0.9;
    old.speed_decimals = 1;
    old.speed_int_digits = 3;
    old.track_decimals = 1;
    old.track_int_digits = 3;
    old.magnetic_variation_deg = -3.1;
    old.rmc_mode = '\0';

    NavSample s;
    s.fields = NavSample::kTime | NavSample::kPosition | NavSample::kVelocity;
    s.t = core::GpsTime{core::Nanos{gps_ns("1994-03-23T12:35:19Z")}};
    s.lat_deg = 48.0 + 7.038 / 60.0;
    s.lon_deg = 11.0 + 31.0 / 60.0;
    s.height_m = 545.4 + 46.9;
    s.quality = FixQuality::Autonomous;
    s.satellites = 8;
    const double v = 22.4 * 1852.0 / 3600.0;
    s.velocity_ned_mps = {v * std::cos(rad(84.4)), v * std::sin(rad(84.4)), 0.0};
    EXPECT_EQ(encode_gga(s, old), kGgaVector + "\r\n");
    EXPECT_EQ(encode_rmc(s, old), kRmcVector + "\r\n");

    NavSample h;
    h.fields = NavSample::kHeading;
    h.heading_rad = rad(274.07);
    EXPECT_EQ(encode_hdt(h), kHdtVector + "\r\n");

    NavSample z;
    z.fields = NavSample::kTime;
    z.t = core::GpsTime{core::Nanos{gps_ns("2004-03-11T16:00:12.71Z")}};
    EncodeOptions zo;
    zo.zda_zone_hours = -1;
    EXPECT_EQ(encode_zda(z, zo), kZdaVector + "\r\n");

    NavSample p;
    p.fields = NavSample::kTime | NavSample::kAttitude;
    p.t = core::GpsTime{core::Nanos{gps_ns("2020-01-01T08:53:35Z")}};
    p.heading_rad = rad(224.19);
    p.roll_rad = rad(-1.26);
    p.pitch_rad = rad(0.83);
    EncodeOptions po;
    po.roll_sigma_deg = 0.101;
    po.pitch_sigma_deg = 0.113;
    po.heading_sigma_deg = 0.267;
    po.aiding_status = 1;
    po.imu_status = 0;
    EXPECT_EQ(encode_pashr(p, po), kPashrVector + "\r\n");

    NavSample a;
    a.fields = NavSample::kTime | NavSample::kHeading;
    a.t = core::GpsTime{core::Nanos{gps_ns("2020-01-01T18:10:59.6Z")}};
    a.heading_rad = rad(149.4688);
    a.pitch_rad = rad(0.0134);
    a.quality = FixQuality::RtkFixed;
    a.satellites = 6;
    EncodeOptions ao;
    ao.avr_range_m = 60.191;
    ao.avr_pdop = 2.5;
    EXPECT_EQ(encode_ptnl_avr(a, ao), kAvrVector + "\r\n");
}

TEST(NmeaFields, latitude_longitude_and_their_range_checks) {
    EXPECT_NEAR(*parse_latitude("4205.733476", "N"), 42.0 + 5.733476 / 60.0, 1e-13);
    EXPECT_NEAR(*parse_longitude("08802.041110", "W"), -(88.0 + 2.04111 / 60.0), 1e-13);
    EXPECT_NEAR(*parse_latitude("3345.5", "S"), -(33.0 + 45.5 / 60.0), 1e-13);
    EXPECT_DOUBLE_EQ(*parse_latitude("9000.000", "N"), 90.0);
    EXPECT_FALSE(parse_latitude("9000.001", "N"));   // beyond the pole
    EXPECT_FALSE(parse_latitude("9100.000", "N"));   // lat > 90
    EXPECT_FALSE(parse_latitude("4260.000", "N"));   // minutes >= 60
    EXPECT_FALSE(parse_longitude("18000.01", "E"));  // lon > 180
    EXPECT_FALSE(parse_latitude("4205.7", "E"));     // wrong hemisphere letter
    EXPECT_FALSE(parse_latitude("4205.7", ""));
    EXPECT_FALSE(parse_latitude("-4205.7", "N"));  // signs are the hemisphere's job
    EXPECT_FALSE(parse_latitude("nan", "N"));
    EXPECT_FALSE(parse_latitude("42", "N"));       // no minutes
    EXPECT_FALSE(parse_latitude("12345.0", "N"));  // three degree digits in a latitude
}

TEST(NmeaFields, numbers_reject_nan_inf_exponents_and_junk) {
    EXPECT_DOUBLE_EQ(*parse_number("+00.83"), 0.83);
    EXPECT_DOUBLE_EQ(*parse_number("-1.26"), -1.26);
    EXPECT_DOUBLE_EQ(*parse_number(".5"), 0.5);
    EXPECT_DOUBLE_EQ(*parse_number("7"), 7.0);
    for (const char* bad : {"nan", "NaN", "inf", "-inf", "1e5", "0x10", "1.2.3", "", "+", ".", "-",
                            "1,2", " 1", "1 "}) {
        EXPECT_FALSE(parse_number(bad)) << bad;
    }
    EXPECT_EQ(*parse_int("08", 0, 99), 8);
    EXPECT_FALSE(parse_int("8.0", 0, 99));
    EXPECT_FALSE(parse_int("100", 0, 99));
}

TEST(NmeaFields, utc_time_is_exact_and_accepts_leap_second_only_at_2359) {
    EXPECT_EQ(parse_utc_time("204132.123456789")->ns_of_day(),
              (20 * 3600 + 41 * 60 + 32) * 1'000'000'000LL + 123'456'789);
    EXPECT_EQ(parse_utc_time("000000")->ns_of_day(), 0);
    EXPECT_EQ(parse_utc_time("235960.5")->ns_of_day(), 86'400'500'000'000LL);
    EXPECT_FALSE(parse_utc_time("235860"));  // :60 outside 23:59
    EXPECT_FALSE(parse_utc_time("240000"));
    EXPECT_FALSE(parse_utc_time("126000"));
    EXPECT_FALSE(parse_utc_time("123561"));
    EXPECT_FALSE(parse_utc_time("12351"));
    EXPECT_FALSE(parse_utc_time("123519.1234567891"));  // more than ns resolution
    EXPECT_FALSE(parse_utc_time("123519,0"));
    EXPECT_FALSE(parse_utc_time("12a519"));
}

TEST(NmeaFields, two_digit_years_map_to_1980_through_2079) {
    EXPECT_EQ(*parse_ddmmyy("190214"), (Date{2014, 2, 19}));
    EXPECT_EQ(*parse_ddmmyy("010180"), (Date{1980, 1, 1}));
    EXPECT_EQ(*parse_ddmmyy("311279"), (Date{2079, 12, 31}));
    EXPECT_EQ(*parse_ddmmyy("290200"), (Date{2000, 2, 29}));  // 2000 is a leap year
    EXPECT_FALSE(parse_ddmmyy("290201"));
    EXPECT_FALSE(parse_ddmmyy("011314"));  // month 13
    EXPECT_FALSE(parse_ddmmyy("000114"));
    EXPECT_FALSE(parse_ddmmyy("320114"));
    EXPECT_FALSE(parse_ddmmyy("1902014"));
    EXPECT_EQ(Date::from_unix_days((Date{2014, 2, 19}).unix_days()), (Date{2014, 2, 19}));
    EXPECT_EQ((Date{1970, 1, 2}).unix_days(), 1);
}

}  // namespace
}  // namespace mirage::nmea
