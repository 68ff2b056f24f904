// SPDX-License-Identifier: Apache-2.0
#include "mirage/nmea/fields.hpp"

#include <charconv>
#include <chrono>
#include <cmath>

#include "mirage/core/time.hpp"

namespace mirage::nmea {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

bool all_digits(std::string_view s) {
    for (char c : s) {
        if (!is_digit(c)) return false;
    }
    return !s.empty();
}

int two_digits(std::string_view s) { return (s[0] - '0') * 10 + (s[1] - '0'); }

// Unsigned "digits[.digits]"; no sign. `allow_bare_fraction` also takes ".5" (some talkers
// drop the leading zero), never a lone ".".
std::optional<double> parse_unsigned_decimal(std::string_view s, bool allow_bare_fraction = false) {
    const std::size_t dot = s.find('.');
    const std::string_view ip = s.substr(0, dot);
    const std::string_view fp =
        dot == std::string_view::npos ? std::string_view{} : s.substr(dot + 1);
    if (!all_digits(ip) && !(allow_bare_fraction && ip.empty() && !fp.empty())) {
        return std::nullopt;
    }
    if (!fp.empty() && !all_digits(fp)) return std::nullopt;
    double v = 0.0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v, std::chars_format::fixed);
    if (r.ec != std::errc{} || r.ptr != s.data() + s.size() || !std::isfinite(v)) {
        return std::nullopt;
    }
    return v;
}

// `value` is [d]dd(d)mm[.mmmm]: the last two integer digits are minutes.
std::optional<double> parse_degrees_minutes(std::string_view value, std::size_t max_deg_digits,
                                            double max_deg) {
    const std::size_t dot = value.find('.');
    const std::size_t int_len = dot == std::string_view::npos ? value.size() : dot;
    if (int_len < 3 || int_len > max_deg_digits + 2) return std::nullopt;
    const std::string_view deg_text = value.substr(0, int_len - 2);
    if (!all_digits(deg_text)) return std::nullopt;
    int deg = 0;
    for (char c : deg_text) deg = deg * 10 + (c - '0');
    const auto minutes = parse_unsigned_decimal(value.substr(int_len - 2));
    if (!minutes || *minutes >= 60.0) return std::nullopt;
    const double d = deg + *minutes / 60.0;
    if (d > max_deg) return std::nullopt;
    return d;
}

}  // namespace

std::optional<double> parse_number(std::string_view text) {
    if (text.size() > 40) return std::nullopt;
    bool negative = false;
    if (!text.empty() && (text.front() == '+' || text.front() == '-')) {
        negative = text.front() == '-';
        text.remove_prefix(1);
    }
    const auto v = parse_unsigned_decimal(text, true);
    if (!v) return std::nullopt;
    return negative ? -*v : *v;
}

std::optional<int> parse_int(std::string_view text, int lo, int hi) {
    if (text.size() > 9) return std::nullopt;
    bool negative = false;
    if (!text.empty() && (text.front() == '+' || text.front() == '-')) {
        negative = text.front() == '-';
        text.remove_prefix(1);
    }
    if (!all_digits(text)) return std::nullopt;
    int v = 0;
    for (char c : text) v = v * 10 + (c - '0');
    if (negative) v = -v;
    if (v < lo || v > hi) return std::nullopt;
    return v;
}

std::int64_t UtcTime::ns_of_day() const {
    return ((hour * 60LL + minute) * 60LL + second) * core::kNsPerSecond + frac_ns;
}

std::optional<UtcTime> parse_utc_time(std::string_view text) {
    if (text.size() < 6 || !all_digits(text.substr(0, 6))) return std::nullopt;
    UtcTime t;
    t.hour = two_digits(text.substr(0, 2));
    t.minute = two_digits(text.substr(2, 2));
    t.second = two_digits(text.substr(4, 2));
    if (text.size() > 6) {
        // Exact fraction: up to 9 digits scaled to ns, no float arithmetic.
        const std::string_view frac = text.substr(7);
        if (text[6] != '.' || frac.size() > 9 || (!frac.empty() && !all_digits(frac))) {
            return std::nullopt;
        }
        std::int64_t ns = 0;
        for (std::size_t i = 0; i < 9; ++i) ns = ns * 10 + (i < frac.size() ? frac[i] - '0' : 0);
        t.frac_ns = ns;
    }
    if (t.hour > 23 || t.minute > 59 || t.second > 60) return std::nullopt;
    if (t.second == 60 && (t.hour != 23 || t.minute != 59)) return std::nullopt;
    return t;
}

std::int64_t Date::unix_days() const {
    using namespace std::chrono;
    return sys_days{std::chrono::year{year} / std::chrono::month{static_cast<unsigned>(month)} /
                    std::chrono::day{static_cast<unsigned>(day)}}
        .time_since_epoch()
        .count();
}

Date Date::from_unix_days(std::int64_t days) {
    using namespace std::chrono;
    const year_month_day ymd{sys_days{std::chrono::days{days}}};
    return {static_cast<int>(ymd.year()), static_cast<int>(static_cast<unsigned>(ymd.month())),
            static_cast<int>(static_cast<unsigned>(ymd.day()))};
}

std::optional<Date> make_date(int year, int month, int day) {
    using namespace std::chrono;
    // Up to 2200: later dates have no int64 ns since 1970 (fuzz_nmea found a ZDA of year 2420).
    if (year < 1980 || year > 2200 || month < 1 || month > 12 || day < 1 || day > 31) {
        return std::nullopt;
    }
    const year_month_day ymd{std::chrono::year{year},
                             std::chrono::month{static_cast<unsigned>(month)},
                             std::chrono::day{static_cast<unsigned>(day)}};
    if (!ymd.ok()) return std::nullopt;
    return Date{year, month, day};
}

std::optional<Date> parse_ddmmyy(std::string_view text) {
    if (text.size() != 6 || !all_digits(text)) return std::nullopt;
    const int yy = two_digits(text.substr(4, 2));
    return make_date(yy < 80 ? 2000 + yy : 1900 + yy, two_digits(text.substr(2, 2)),
                     two_digits(text.substr(0, 2)));
}

std::optional<double> parse_latitude(std::string_view value, std::string_view hemisphere) {
    if (hemisphere != "N" && hemisphere != "S") return std::nullopt;
    const auto d = parse_degrees_minutes(value, 2, 90.0);
    if (!d) return std::nullopt;
    return hemisphere == "S" ? -*d : *d;
}

std::optional<double> parse_longitude(std::string_view value, std::string_view hemisphere) {
    if (hemisphere != "E" && hemisphere != "W") return std::nullopt;
    const auto d = parse_degrees_minutes(value, 3, 180.0);
    if (!d) return std::nullopt;
    return hemisphere == "W" ? -*d : *d;
}

std::int64_t gps_ns_from_utc(const Date& date, const UtcTime& time) {
    const std::int64_t day_ns = date.unix_days() * 86'400 * core::kNsPerSecond;
    if (time.second == 60) {
        // 23:59:60 has no POSIX number: one second after 23:59:59, before GPS − UTC steps.
        const std::int64_t before = day_ns + 86'399 * core::kNsPerSecond;
        return core::gps_from_unix_ns(before).time_since_epoch().count() + core::kNsPerSecond +
               time.frac_ns;
    }
    return core::gps_from_unix_ns(day_ns + time.ns_of_day()).time_since_epoch().count();
}

}  // namespace mirage::nmea
