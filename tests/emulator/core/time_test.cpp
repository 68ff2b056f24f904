// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/time.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>

#include "mirage/core/error.hpp"
#include "test_units.hpp"

using namespace mirage::core;

namespace {

using mirage::test::kS;
constexpr std::int64_t kUnix2024 = 1'704'067'200;  // 2024-01-01T00:00:00Z

std::int64_t ns(GpsTime t) { return t.time_since_epoch().count(); }

std::int64_t unix_day(int y, unsigned m, unsigned d) {
    using namespace std::chrono;
    return sys_days{year{y} / month{m} / day{d}}.time_since_epoch().count() * 86'400LL;
}

// IERS Bulletin C: the days whose midnight follows an inserted leap second.
constexpr std::array<std::array<int, 2>, 18> kLeapDates{{{1981, 7},
                                                         {1982, 7},
                                                         {1983, 7},
                                                         {1985, 7},
                                                         {1988, 1},
                                                         {1990, 1},
                                                         {1991, 1},
                                                         {1992, 7},
                                                         {1993, 7},
                                                         {1994, 7},
                                                         {1996, 1},
                                                         {1997, 7},
                                                         {1999, 1},
                                                         {2006, 1},
                                                         {2009, 1},
                                                         {2012, 7},
                                                         {2015, 7},
                                                         {2017, 1}}};

}  // namespace

TEST(GpsTime, new_year_2024_is_week_2295_second_86418) {
    // docs/physics.md §3.1 test vector.
    const GpsTime t = parse_time("2024-01-01T00:00:00Z");
    const GpsWeekTime w = to_week_time(t);
    EXPECT_EQ(w.week, 2295);
    EXPECT_EQ(w.ns_of_week, 86'418 * kS);
    EXPECT_EQ(t, gps_from_unix_ns(kUnix2024 * kS));
    EXPECT_EQ(t, parse_time("2024-01-01 00:00:00"));
    EXPECT_EQ(ns(t), (kUnix2024 - kGpsEpochUnixSeconds + 18) * kS);
    EXPECT_EQ(leap_seconds_at_gps(t), 18);
}

TEST(GpsTime, gps_epoch_is_zero) {
    EXPECT_EQ(ns(parse_time("1980-01-06T00:00:00Z")), 0);
    EXPECT_EQ(leap_seconds_at_utc(kGpsEpochUnixSeconds), 0);
}

TEST(GpsTime, leap_table_steps_by_one_at_each_bulletin_c_date) {
    int expected = 0;
    for (const auto& [y, m] : kLeapDates) {
        const std::int64_t midnight = unix_day(y, static_cast<unsigned>(m), 1);
        EXPECT_EQ(leap_seconds_at_utc(midnight - 1), expected) << y << "-" << m;
        ++expected;
        EXPECT_EQ(leap_seconds_at_utc(midnight), expected) << y << "-" << m;
        // In GPS time the step lands two GPS seconds after UTC 23:59:59 (23:59:60 between).
        const GpsTime before = gps_from_unix_ns((midnight - 1) * kS);
        const GpsTime after = gps_from_unix_ns(midnight * kS);
        EXPECT_EQ(ns(after) - ns(before), 2 * kS);
        EXPECT_EQ(leap_seconds_at_gps(after), expected);
        EXPECT_EQ(leap_seconds_at_gps(after - Nanos{1}), expected - 1);
    }
    EXPECT_EQ(expected, 18);
    EXPECT_EQ(leap_seconds_at_utc(kUnix2024), 18);
}

TEST(GpsTime, leap_second_2016_boundary_is_two_gps_seconds) {
    const GpsTime a = parse_time("2016-12-31T23:59:59Z");
    const GpsTime leap = parse_time("2016-12-31T23:59:60Z");
    const GpsTime b = parse_time("2017-01-01T00:00:00Z");
    EXPECT_EQ(ns(b) - ns(a), 2 * kS);
    EXPECT_EQ(ns(leap) - ns(a), kS);
    EXPECT_EQ(ns(parse_time("2016-12-31T23:59:60.5Z")) - ns(a), kS + kS / 2);
    // The inserted second has no POSIX number of its own: it shares 00:00:00's.
    EXPECT_EQ(unix_ns_from_gps(leap), unix_day(2017, 1, 1) * kS);
    EXPECT_THROW(parse_time("2016-12-30T23:59:60Z"), mirage::ConfigError);
    EXPECT_THROW(parse_time("2016-12-31T23:58:60Z"), mirage::ConfigError);
}

TEST(GpsTime, unix_round_trip_is_exact_around_every_leap_second) {
    std::mt19937_64 rng(7);
    std::uniform_int_distribution<std::int64_t> jitter(-3 * kS, 3 * kS);
    for (const auto& [y, m] : kLeapDates) {
        const std::int64_t midnight = unix_day(y, static_cast<unsigned>(m), 1) * kS;
        for (int i = 0; i < 2000; ++i) {
            const std::int64_t u = midnight + jitter(rng);
            ASSERT_EQ(unix_ns_from_gps(gps_from_unix_ns(u)), u);
        }
    }
}

TEST(GpsTime, gps_round_trip_is_exact_outside_inserted_seconds) {
    std::mt19937_64 rng(11);
    const std::int64_t lo = 0, hi = ns(parse_time("2030-01-01T00:00:00Z"));
    std::uniform_int_distribution<std::int64_t> dist(lo, hi);
    int checked = 0;
    for (int i = 0; i < 100'000; ++i) {
        const GpsTime t{Nanos{dist(rng)}};
        const GpsTime back = gps_from_unix_ns(unix_ns_from_gps(t));
        // Only the 18 inserted seconds (23:59:60) do not come back; hitting one is ~1e-8 likely.
        if (leap_seconds_at_gps(t) != leap_seconds_at_gps(t + Nanos{kS})) continue;
        ASSERT_EQ(back, t);
        ++checked;
    }
    EXPECT_GT(checked, 99'990);
}

TEST(GpsTime, a_day_later_plus_one_ns_is_exact_everywhere) {
    const GpsTime t0 = parse_time("2024-01-01T00:00:00Z");
    const GpsTime t = t0 + Nanos{86'400 * kS + 1};
    EXPECT_EQ(unix_ns_from_gps(t) - unix_ns_from_gps(t0), 86'400 * kS + 1);
    const GpsWeekTime w = to_week_time(t);
    EXPECT_EQ(w.week, 2295);
    EXPECT_EQ(w.ns_of_week, (86'418 + 86'400) * kS + 1);
    EXPECT_EQ(from_week_time(w.week, w.ns_of_week), t);
    EXPECT_EQ(parse_time("2024-01-02T00:00:00.000000001Z"), t);
    EXPECT_EQ(parse_decimal_seconds(format_decimal_seconds(t.time_since_epoch())),
              t.time_since_epoch());
    // Every ns of a day-long sweep keeps its identity through week time and POSIX.
    for (std::int64_t k = 0; k <= 86'400; k += 97) {
        const GpsTime tk = t0 + Nanos{k * kS + k};  // a different ns offset each second
        const GpsWeekTime wk = to_week_time(tk);
        ASSERT_EQ(from_week_time(wk.week, wk.ns_of_week), tk);
        ASSERT_EQ(unix_ns_from_gps(tk), kUnix2024 * kS + k * kS + k);
    }
}

TEST(GpsTime, week_time_wraps_at_week_boundaries) {
    const GpsTime start = from_week_time(2295, 0);
    EXPECT_EQ(to_week_time(start - Nanos{1}).week, 2294);
    EXPECT_EQ(to_week_time(start - Nanos{1}).ns_of_week, kSecondsPerWeek * kS - 1);
    EXPECT_EQ(to_week_time(start).week, 2295);
    EXPECT_EQ(to_week_time(start).ns_of_week, 0);
    // Before the epoch, floor division keeps ns_of_week non-negative.
    EXPECT_EQ(to_week_time(GpsTime{Nanos{-1}}).week, -1);
    EXPECT_EQ(to_week_time(GpsTime{Nanos{-1}}).ns_of_week, kSecondsPerWeek * kS - 1);
}

TEST(GpsTime, adjusted_standard_time_subtracts_one_billion_seconds) {
    const GpsTime t = parse_time("2024-01-01T00:00:00Z");
    EXPECT_EQ(adjusted_standard_gps_seconds(t), 388'102'418.0);
    EXPECT_EQ(adjusted_standard_gps_seconds(t + Nanos{kS / 2}), 388'102'418.5);
    EXPECT_EQ(adjusted_standard_gps_seconds(GpsTime{Nanos{1'000'000'000 * kS}}), 0.0);
    EXPECT_EQ(adjusted_standard_gps_seconds(GpsTime{Nanos{999'999'999 * kS + kS / 4}}), -0.75);
    // 1 µs steps survive the double (ulp at 3.9e8 s is 6e-8 s).
    EXPECT_NEAR(adjusted_standard_gps_seconds(t + Nanos{1000}) - 388'102'418.0, 1e-6, 1e-7);
}

TEST(GpsTime, parse_time_reads_fractions_and_gps_seconds_exactly) {
    const GpsTime t0 = parse_time("2024-01-01T00:00:00Z");
    EXPECT_EQ(ns(parse_time("2024-01-01T00:00:00.000000001Z")) - ns(t0), 1);
    EXPECT_EQ(ns(parse_time("2024-01-01 00:00:00.5")) - ns(t0), kS / 2);
    EXPECT_EQ(ns(parse_time("  2024-01-01t00:00:00.123z ")) - ns(t0), 123'000'000);
    EXPECT_EQ(ns(parse_time("gps:1388534418.000000123")), 1'388'534'418'000'000'123);
    EXPECT_EQ(ns(parse_time("gps:1388102418")), ns(t0));
}

TEST(GpsTime, parse_time_rejects_malformed_text_naming_it) {
    for (const char* bad : {"2024-13-01T00:00:00Z", "2024-02-30 00:00:00", "yesterday",
                            "2024-01-01T24:00:00Z", "2024-01-01T00:60:00Z", "2024-1-01T00:00:00Z",
                            "2024-01-01T00:00:00.Z", "2024-01-01T00:00:00.1234567891Z",
                            "2024-01-01T00:00:00+01:00", "gps:", "gps:1e9", "gps:12.3.4", ""}) {
        try {
            parse_time(bad);
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const mirage::ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos)
                << e.what();
        }
    }
}

// Years whose ns since 1970 do not fit 64 bits are refused, not wrapped (fuzz_trajectory_csv).
TEST(GpsTime, parse_time_refuses_years_outside_1900_to_2200) {
    for (const char* far : {"1012-03-01T12:00:00Z", "1899-12-31T23:59:59Z", "2201-01-01 00:00:00",
                            "9999-12-31T23:59:59Z"}) {
        try {
            parse_time(far);
            ADD_FAILURE() << "accepted '" << far << "'";
        } catch (const mirage::ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("year outside 1900..2200"), std::string::npos)
                << e.what();
        }
    }
    EXPECT_EQ(unix_ns_from_gps(parse_time("1900-01-01T00:00:00Z")), -2'208'988'800'000'000'000);
    EXPECT_EQ(unix_ns_from_gps(parse_time("2200-12-31T23:59:59Z")), 7'289'654'399'000'000'000);
}

TEST(GpsTime, decimal_seconds_parse_exactly_or_not_at_all) {
    EXPECT_EQ(parse_decimal_seconds("1388534418.000000123")->count(), 1'388'534'418'000'000'123);
    EXPECT_EQ(parse_decimal_seconds("-1.5")->count(), -1'500'000'000);
    EXPECT_EQ(parse_decimal_seconds("+2")->count(), 2 * kS);
    EXPECT_EQ(parse_decimal_seconds(".25")->count(), kS / 4);
    EXPECT_EQ(parse_decimal_seconds("7.")->count(), 7 * kS);
    EXPECT_EQ(parse_decimal_seconds("1.5000000000000")->count(), 1'500'000'000);  // zeros ok
    EXPECT_EQ(parse_decimal_seconds("9223372036.854775807")->count(), INT64_MAX);
    for (const char* bad : {"", ".", "-", "1.0000000001", "1e9", " 1", "1 ", "0x10", "nan",
                            "9223372036.854775808", "99999999999"}) {
        EXPECT_FALSE(parse_decimal_seconds(bad).has_value()) << bad;
    }
}

TEST(GpsTime, decimal_seconds_format_with_nine_digits) {
    EXPECT_EQ(format_decimal_seconds(Nanos{0}), "0.000000000");
    EXPECT_EQ(format_decimal_seconds(Nanos{-500'000'000}), "-0.500000000");
    EXPECT_EQ(format_decimal_seconds(Nanos{1'388'534'418'000'000'123}), "1388534418.000000123");
    EXPECT_EQ(format_decimal_seconds(Nanos{INT64_MIN}), "-9223372036.854775808");
}
