// SPDX-License-Identifier: Apache-2.0
#include "mirage/core/time.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <limits>

#include "mirage/core/error.hpp"

namespace mirage::core {
namespace {

using std::chrono::day;
using std::chrono::month;
using std::chrono::sys_days;
using std::chrono::year;

struct LeapStep {
    std::int64_t unix_s;  // UTC midnight at which the new GPS − UTC value takes effect
    int gps_minus_utc;
};

constexpr std::int64_t unix_seconds(int y, unsigned m, unsigned d) {
    return static_cast<std::int64_t>(
               sys_days{year{y} / month{m} / day{d}}.time_since_epoch().count()) *
           86'400;
}

// Every leap second since the GPS epoch (IERS Bulletin C; none announced after 2017-01-01).
// GPS − UTC was 0 at the epoch, 1980-01-06.
constexpr std::array<LeapStep, 18> kLeapSteps{{
    {unix_seconds(1981, 7, 1), 1},
    {unix_seconds(1982, 7, 1), 2},
    {unix_seconds(1983, 7, 1), 3},
    {unix_seconds(1985, 7, 1), 4},
    {unix_seconds(1988, 1, 1), 5},
    {unix_seconds(1990, 1, 1), 6},
    {unix_seconds(1991, 1, 1), 7},
    {unix_seconds(1992, 7, 1), 8},
    {unix_seconds(1993, 7, 1), 9},
    {unix_seconds(1994, 7, 1), 10},
    {unix_seconds(1996, 1, 1), 11},
    {unix_seconds(1997, 7, 1), 12},
    {unix_seconds(1999, 1, 1), 13},
    {unix_seconds(2006, 1, 1), 14},
    {unix_seconds(2009, 1, 1), 15},
    {unix_seconds(2012, 7, 1), 16},
    {unix_seconds(2015, 7, 1), 17},
    {unix_seconds(2017, 1, 1), 18},
}};
static_assert(unix_seconds(1980, 1, 6) == kGpsEpochUnixSeconds);

// GPS second at which a step takes effect (the instant after the inserted 23:59:60).
constexpr std::int64_t gps_seconds_of_step(const LeapStep& s) {
    return s.unix_s - kGpsEpochUnixSeconds + s.gps_minus_utc;
}

constexpr std::int64_t floor_div(std::int64_t a, std::int64_t b) {
    std::int64_t q = a / b;
    return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

[[noreturn]] void bad_time(const std::string& text, const std::string& why) {
    throw ConfigError("time '" + text + "': " + why +
                      " (expected 'YYYY-MM-DDTHH:MM:SS[.f]Z', 'YYYY-MM-DD HH:MM:SS[.f]' or "
                      "'gps:<seconds>')");
}

// Reads exactly n decimal digits at pos.
bool read_digits(std::string_view s, std::size_t& pos, std::size_t n, int& out) {
    if (pos + n > s.size()) return false;
    int v = 0;
    for (std::size_t i = 0; i < n; ++i) {
        char c = s[pos + i];
        if (c < '0' || c > '9') return false;
        v = v * 10 + (c - '0');
    }
    out = v;
    pos += n;
    return true;
}

bool expect_char(std::string_view s, std::size_t& pos, char c) {
    if (pos >= s.size() || s[pos] != c) return false;
    ++pos;
    return true;
}

}  // namespace

int leap_seconds_at_utc(std::int64_t unix_seconds_utc) {
    int leap = 0;
    for (const auto& s : kLeapSteps) {
        if (unix_seconds_utc < s.unix_s) break;
        leap = s.gps_minus_utc;
    }
    return leap;
}

int leap_seconds_at_gps(GpsTime t) {
    const std::int64_t gps_s = floor_div(t.time_since_epoch().count(), kNsPerSecond);
    int leap = 0;
    for (const auto& s : kLeapSteps) {
        if (gps_s < gps_seconds_of_step(s)) break;
        leap = s.gps_minus_utc;
    }
    return leap;
}

GpsTime gps_from_unix_ns(std::int64_t unix_ns) {
    const int leap = leap_seconds_at_utc(floor_div(unix_ns, kNsPerSecond));
    return GpsTime{Nanos{unix_ns - kGpsEpochUnixSeconds * kNsPerSecond + leap * kNsPerSecond}};
}

// An inserted leap second (UTC 23:59:60) has no POSIX number of its own; it maps onto the
// following 00:00:00, as GPS − UTC only changes at the end of it.
std::int64_t unix_ns_from_gps(GpsTime t) {
    const int leap = leap_seconds_at_gps(t);
    return t.time_since_epoch().count() + kGpsEpochUnixSeconds * kNsPerSecond - leap * kNsPerSecond;
}

GpsWeekTime to_week_time(GpsTime t) {
    constexpr std::int64_t kNsPerWeek = kSecondsPerWeek * kNsPerSecond;
    const std::int64_t ns = t.time_since_epoch().count();
    const std::int64_t week = floor_div(ns, kNsPerWeek);
    return {static_cast<std::int32_t>(week), ns - week * kNsPerWeek};
}

GpsTime from_week_time(std::int32_t week, std::int64_t ns_of_week) {
    return GpsTime{
        Nanos{static_cast<std::int64_t>(week) * kSecondsPerWeek * kNsPerSecond + ns_of_week}};
}

std::optional<Nanos> parse_decimal_seconds(std::string_view text) {
    std::size_t pos = 0;
    bool negative = false;
    if (pos < text.size() && (text[pos] == '-' || text[pos] == '+')) {
        negative = text[pos] == '-';
        ++pos;
    }
    constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
    std::int64_t whole = 0;
    std::size_t int_digits = 0;
    for (; pos < text.size() && text[pos] >= '0' && text[pos] <= '9'; ++pos, ++int_digits) {
        const int digit = text[pos] - '0';
        if (whole > (kMax / kNsPerSecond - digit) / 10) return std::nullopt;
        whole = whole * 10 + digit;
    }
    std::int64_t frac = 0;
    std::size_t frac_digits = 0;
    if (pos < text.size() && text[pos] == '.') {
        ++pos;
        for (; pos < text.size() && text[pos] >= '0' && text[pos] <= '9'; ++pos, ++frac_digits) {
            const int digit = text[pos] - '0';
            if (frac_digits < 9) {
                frac = frac * 10 + digit;
            } else if (digit != 0) {
                return std::nullopt;  // sub-nanosecond digits would be silently lost
            }
        }
    }
    if (pos != text.size() || int_digits + frac_digits == 0) return std::nullopt;
    for (std::size_t i = frac_digits; i < 9; ++i) frac *= 10;
    if (frac > kMax - whole * kNsPerSecond) return std::nullopt;
    const std::int64_t ns = whole * kNsPerSecond + frac;
    return Nanos{negative ? -ns : ns};
}

std::string format_decimal_seconds(Nanos d) {
    const std::int64_t ns = d.count();
    // Magnitude as unsigned so INT64_MIN does not overflow.
    std::uint64_t mag =
        ns < 0 ? 0 - static_cast<std::uint64_t>(ns) : static_cast<std::uint64_t>(ns);
    // Digits from the right: 9 fractional digits, the point, then the whole seconds.
    char buf[32];
    char* p = buf + sizeof buf;
    for (int i = 0; i < 9; ++i, mag /= 10) *--p = static_cast<char>('0' + mag % 10);
    *--p = '.';
    do {
        *--p = static_cast<char>('0' + mag % 10);
        mag /= 10;
    } while (mag != 0);
    if (ns < 0) *--p = '-';
    return std::string(p, buf + sizeof buf);
}

GpsTime parse_time(const std::string& text) {
    constexpr int kMinYear = 1900, kMaxYear = 2200;
    std::string_view s = text;
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);

    if (s.substr(0, 4) == "gps:") {
        auto ns = parse_decimal_seconds(s.substr(4));
        if (!ns) bad_time(text, "expected decimal GPS seconds after 'gps:' (at most 9 decimals)");
        return GpsTime{*ns};
    }

    std::size_t pos = 0;
    int y = 0, mo = 0, d = 0, h = 0, mi = 0, sec = 0;
    const bool layout_ok =
        read_digits(s, pos, 4, y) && expect_char(s, pos, '-') && read_digits(s, pos, 2, mo) &&
        expect_char(s, pos, '-') && read_digits(s, pos, 2, d) && pos < s.size() &&
        (s[pos] == 'T' || s[pos] == 't' || s[pos] == ' ') && (++pos, read_digits(s, pos, 2, h)) &&
        expect_char(s, pos, ':') && read_digits(s, pos, 2, mi) && expect_char(s, pos, ':') &&
        read_digits(s, pos, 2, sec);
    if (!layout_ok) bad_time(text, "unrecognised layout");

    std::int64_t frac_ns = 0;
    if (pos < s.size() && s[pos] == '.') {
        std::size_t end = pos + 1;
        while (end < s.size() && s[end] >= '0' && s[end] <= '9') ++end;
        if (end == pos + 1) bad_time(text, "no digits after the decimal point");
        auto f = parse_decimal_seconds(s.substr(pos, end - pos));  // ".123"
        if (!f) bad_time(text, "more than 9 decimal places");
        frac_ns = f->count();
        pos = end;
    }
    if (pos < s.size() && (s[pos] == 'Z' || s[pos] == 'z')) ++pos;
    if (pos != s.size()) bad_time(text, "unexpected trailing characters");

    const std::chrono::year_month_day ymd{year{y}, month{static_cast<unsigned>(mo)},
                                          day{static_cast<unsigned>(d)}};
    if (!ymd.ok()) bad_time(text, "no such date");
    // Beyond these, ns since 1970 overflow 64 bits (fuzz_trajectory_csv found year 1012).
    if (y < kMinYear || y > kMaxYear) bad_time(text, "year outside 1900..2200");
    if (h > 23 || mi > 59 || sec > 60) bad_time(text, "time of day out of range");

    const std::int64_t day_s =
        static_cast<std::int64_t>(sys_days{ymd}.time_since_epoch().count()) * 86'400;
    if (sec == 60) {
        // 23:59:60 exists only where a leap second was inserted at the end of that day.
        const std::int64_t midnight = day_s + 86'400;
        if (h != 23 || mi != 59 ||
            leap_seconds_at_utc(midnight) != leap_seconds_at_utc(midnight - 1) + 1) {
            bad_time(text, "second 60 only exists at an inserted leap second");
        }
        return gps_from_unix_ns((midnight - 1) * kNsPerSecond) + Nanos{kNsPerSecond + frac_ns};
    }
    const std::int64_t unix_s = day_s + h * 3600 + mi * 60 + sec;
    return gps_from_unix_ns(unix_s * kNsPerSecond + frac_ns);
}

}  // namespace mirage::core
