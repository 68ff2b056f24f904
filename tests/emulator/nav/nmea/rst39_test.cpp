// SPDX-License-Identifier: Apache-2.0
// The real OxTS RT capture rst39.log (gpsd test suite; docs/nav-protocols.md §1).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "mirage/nmea/nmea_decoder.hpp"
#include "nmea_test_util.hpp"
#include "test_paths.hpp"

namespace mirage::nmea {
namespace {

using nav::NavSample;
using test::deg;

std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Bytes of the `#` comment lines, without their line ends.
std::uint64_t comment_bytes(const std::string& text) {
    std::uint64_t n = 0;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (!line.empty() && line[0] == '#') n += line.size();
    }
    return n;
}

TEST(NmeaRst39, real_capture_decodes_with_nothing_rejected) {
    MIRAGE_NAVIO_OR_SKIP(path, "rst39.log");
    const std::string text = read_file(path);
    NmeaDecoder d;
    const auto out = test::decode_all(d, text);
    const auto& c = d.counters();
    const auto& n = d.nmea_counters();
    EXPECT_EQ(c.rejected(), 0u);
    EXPECT_EQ(c.unsupported, 0u);
    EXPECT_EQ(n.pashr, 100u);
    EXPECT_EQ(n.gga, 40u);
    EXPECT_EQ(n.rmc, 4u);
    EXPECT_EQ(n.hdt, 4u);
    EXPECT_EQ(n.zda, 4u);
    EXPECT_EQ(c.messages_ok, 152u);
    EXPECT_EQ(c.garbage_bytes, comment_bytes(text));  // only the comment lines
    EXPECT_EQ(n.before_date, 1u);                     // the first $PASHR precedes the first $GPRMC
    EXPECT_EQ(out.size(), 151u);
    EXPECT_EQ(c.samples, 151u);

    int gga = 0, att = 0;
    double first_heading = -1, last_heading = -1;
    for (const NavSample& s : out) {
        if (s.has(NavSample::kPosition)) {
            ++gga;
            EXPECT_NEAR(s.lat_deg, 42.0957, 0.0005);
            EXPECT_NEAR(s.lon_deg, -88.0340, 0.0005);
            EXPECT_TRUE(s.has(NavSample::kHeightIsMsl));  // the separation field is empty
            EXPECT_NEAR(s.height_m, 221.9, 0.5);
            EXPECT_EQ(s.quality, nav::FixQuality::Differential);
            EXPECT_TRUE(s.satellites == 8 || s.satellites == 9) << int(s.satellites);
        }
        if (s.has(NavSample::kAttitude)) {
            ++att;
            if (first_heading < 0) first_heading = deg(s.heading_rad);
            last_heading = deg(s.heading_rad);
        }
        // Every sample is dated 2014-02-19 UTC, 20:41:32 .. 20:41:36.
        const std::int64_t unix_s = core::unix_ns_from_gps(s.t) / 1'000'000'000;
        EXPECT_GE(unix_s, 1392842492);  // 2014-02-19T20:41:32Z
        EXPECT_LE(unix_s, 1392842496);
    }
    EXPECT_EQ(gga, 40);
    EXPECT_EQ(att, 99);
    EXPECT_NEAR(first_heading, 10.99, 1e-9);  // 10.51 is the undated first line
    EXPECT_NEAR(last_heading, 74.42, 1e-9);
    std::printf("rst39: %llu samples, %llu garbage bytes, heading %.2f -> %.2f deg\n",
                static_cast<unsigned long long>(c.samples),
                static_cast<unsigned long long>(c.garbage_bytes), first_heading, last_heading);
}

TEST(NmeaRst39, date_hint_dates_the_first_line_and_splits_change_nothing) {
    MIRAGE_NAVIO_OR_SKIP(path, "rst39.log");
    const std::string text = read_file(path);
    NmeaDecoder whole;
    whole.set_date_hint(Date{2014, 2, 19});
    const auto ref = test::decode_all(whole, text);
    ASSERT_EQ(ref.size(), 152u);
    ASSERT_TRUE(ref[0].has(NavSample::kAttitude));
    EXPECT_NEAR(deg(ref[0].heading_rad), 10.51, 1e-9);
    EXPECT_EQ(ref[0].t.time_since_epoch().count(), test::gps_ns("2014-02-19T20:41:32Z"));
    for (std::uint32_t seed = 1; seed <= 8; ++seed) {
        NmeaDecoder d;
        d.set_date_hint(Date{2014, 2, 19});
        const auto got = test::decode_split(d, text, seed, seed * 7);
        ASSERT_EQ(got.size(), ref.size());
        for (std::size_t i = 0; i < ref.size(); ++i) EXPECT_TRUE(test::same_sample(got[i], ref[i]));
    }
}

}  // namespace
}  // namespace mirage::nmea
