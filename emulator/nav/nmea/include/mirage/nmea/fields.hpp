// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <optional>
#include <string_view>

namespace mirage::nmea {

// Field value parsers. Each returns nullopt on malformed or out-of-range text; callers check for
// an empty field (= no data) first. None of them accepts "nan", "inf", exponents or hex.

// "[+|-]digits[.digits]" (at least one digit) as a double.
std::optional<double> parse_number(std::string_view text);
// "[+|-]digits" as an integer within [lo, hi].
std::optional<int> parse_int(std::string_view text, int lo, int hi);

// UTC time of day `hhmmss[.f…]` (up to 9 fraction digits), read exactly. Seconds may be 60
// (an inserted leap second) only at 23:59.
struct UtcTime {
    int hour = 0, minute = 0, second = 0;
    std::int64_t frac_ns = 0;
    // ns since 00:00:00 of the day; 23:59:60.x gives 86 400 s + x.
    std::int64_t ns_of_day() const;
};
std::optional<UtcTime> parse_utc_time(std::string_view text);

// A calendar date, checked (day within the month, leap years).
struct Date {
    int year = 0, month = 0, day = 0;
    std::int64_t unix_days() const;  // days since 1970-01-01
    static Date from_unix_days(std::int64_t days);
    friend bool operator==(const Date&, const Date&) = default;
};
// A valid calendar date of 1980..2200; nullopt otherwise.
std::optional<Date> make_date(int year, int month, int day);
// RMC `ddmmyy`; two-digit years map to 1980–2079.
std::optional<Date> parse_ddmmyy(std::string_view text);

// Latitude `ddmm.mmmm` + N/S, longitude `dddmm.mmmm` + E/W, to signed degrees. The last two
// integer digits are minutes (< 60); degrees at most 90 / 180.
std::optional<double> parse_latitude(std::string_view value, std::string_view hemisphere);
std::optional<double> parse_longitude(std::string_view value, std::string_view hemisphere);

// One international knot (exact) in m/s: NMEA speeds over ground are in knots.
inline constexpr double kKnotMps = 1852.0 / 3600.0;

// GPS time of a UTC date and time of day (leap seconds from mirage::core; 23:59:60 lands on the
// inserted second).
std::int64_t gps_ns_from_utc(const Date& date, const UtcTime& time);

}  // namespace mirage::nmea
