// SPDX-License-Identifier: Apache-2.0
#include "mirage/navproto/nav_log.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <type_traits>

#include "mirage/core/error.hpp"
#include "mirage/navcan/oxts_can.hpp"
#include "mirage/navcan/sbg_can.hpp"
#include "mirage/navproto/protocol.hpp"
#include "mirage/ncom/decoder.hpp"
#include "mirage/nmea/nmea_decoder.hpp"
#include "mirage/novatel/decoder.hpp"

namespace mirage::navproto {
namespace {

constexpr std::int64_t kNsPerDay = 86'400'000'000'000;

std::vector<std::uint8_t> read_all(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw IoError("nav log '" + path + "': cannot read (no such file or no permission)");
    std::vector<std::uint8_t> out((std::istreambuf_iterator<char>(f)),
                                  std::istreambuf_iterator<char>());
    if (f.bad()) throw IoError("nav log '" + path + "': read error");
    return out;
}

// The UTC date of the log's first timed sentence, found by a pass without a date hint (which
// drops everything before the first RMC/ZDA); the real pass then starts on that date.
std::optional<nmea::Date> nmea_log_date(std::span<const std::uint8_t> bytes) {
    nmea::NmeaDecoder d;
    std::optional<std::int64_t> first;
    d.feed(bytes, [&](const nav::NavSample& s) {
        if (!first && s.has(nav::NavSample::kTime)) first = core::unix_ns_from_gps(s.t);
    });
    if (!first) return std::nullopt;
    // Floor division: a pre-1970 time never happens in a log, but stay exact anyway.
    const std::int64_t days = *first >= 0 ? *first / kNsPerDay : -((-*first - 1) / kNsPerDay) - 1;
    return nmea::Date::from_unix_days(days);
}

// Keeps a decoded sample (the mapper counts the untimed ones as live does); true if timed.
bool keep(NavLog& log, const nav::NavSample& s) {
    ++log.stats.samples;
    log.samples.push_back(s);
    if (s.has(nav::NavSample::kTime)) return true;
    ++log.stats.untimed_samples;
    return false;
}

// NMEA: one message per line; a line's time is that of the timed sample it yields.
void split_nmea(NavLog& log, const NavLogOptions& opt) {
    nmea::NmeaDecoder d;
    if (auto date = nmea_log_date(log.bytes)) {
        d.set_date_hint(*date);
    } else {
        if (const auto hint = nmea_date_hint(opt.nmea_date.empty() ? "host" : opt.nmea_date))
            d.set_date_hint(*hint);
        log.stats.nmea_date_assumed = opt.nmea_date.empty();
    }
    const std::span<const std::uint8_t> all(log.bytes);
    std::size_t start = 0;
    while (start < all.size()) {
        std::size_t end = start;
        while (end < all.size() && all[end] != '\n') ++end;
        if (end < all.size()) ++end;  // the '\n' belongs to its line
        NavLogMessage m;
        m.offset = start;
        m.size = end - start;
        d.feed(all.subspan(start, end - start), [&](const nav::NavSample& s) {
            if (!keep(log, s)) return;
            if (!m.timed) {
                m.t = s.t;
                m.timed = true;
            }
        });
        log.messages.push_back(m);
        start = end;
    }
    log.stats.decode = d.counters();
}

// Binary protocols: bytes are fed one at a time, and a message ends at the byte that completes
// a timed sample; bytes before it (unsupported logs, garbage) travel with it.
template <class Decoder>
void split_binary(NavLog& log, Decoder& d) {
    const std::span<const std::uint8_t> all(log.bytes);
    std::size_t start = 0;
    bool timed = false;
    core::GpsTime t{};
    const auto on = [&](const nav::NavSample& s) {
        if (!keep(log, s)) return;
        if (!timed) {
            timed = true;
            t = s.t;
        }
    };
    for (std::size_t i = 0; i < all.size(); ++i) {
        d.feed(all.subspan(i, 1), on);
        if (timed) {
            log.messages.push_back({start, i + 1 - start, t, true});
            start = i + 1;
            timed = false;
        }
    }
    d.finish();
    if (start < all.size()) log.messages.push_back({start, all.size() - start, t, false});
    log.stats.decode = d.counters();
}

template <class Decoder>
void decode_can(NavLog& log, Decoder& d) {
    const auto on = [&](const nav::NavSample& s) { keep(log, s); };
    for (const auto& r : log.frames) {
        if constexpr (std::is_same_v<Decoder, navcan::OxtsCanDecoder>)
            d.feed(r.stamped, on);
        else
            d.feed(r.stamped.frame, on);
    }
    d.flush(on);
    log.stats.decode = d.counters();
}

// Untimed messages take the previous timed message's time (the first ones the first time).
void fill_times(std::vector<NavLogMessage>& msgs) {
    std::optional<core::GpsTime> prev;
    for (const auto& m : msgs)
        if (m.timed) {
            prev = m.t;
            break;
        }
    if (!prev) return;
    for (auto& m : msgs) {
        if (m.timed)
            prev = m.t;
        else
            m.t = *prev;
    }
}

}  // namespace

NavLog read_nav_log(const std::string& path, NavProtocol protocol, const NavLogOptions& options) {
    if (protocol == NavProtocol::Dis)
        throw ConfigError("nav log '" + path +
                          "': DIS is read live only (record the PDUs as a pcap with "
                          "`mirage record`)");
    NavLog log;
    log.path = path;
    log.protocol = protocol;
    if (is_can(protocol)) {
        if (!std::filesystem::is_regular_file(path))
            throw IoError("nav log '" + path + "': cannot read (no such file)");
        navcan::CandumpReader reader(path);  // throws IoError naming the file
        navcan::CandumpRecord r;
        while (reader.next(r)) log.frames.push_back(r);
        log.stats.candump = reader.stats();
        log.stats.messages = log.frames.size();
        log.stats.bytes = std::filesystem::file_size(path);
        if (protocol == NavProtocol::OxtsCan) {
            navcan::OxtsCanDecoder d;
            decode_can(log, d);
        } else {
            navcan::SbgCanDecoder d;
            decode_can(log, d);
        }
        return log;
    }
    if (std::filesystem::is_directory(path))
        throw IoError("nav log '" + path + "': cannot read (a directory)");
    log.bytes = read_all(path);
    log.stats.bytes = log.bytes.size();
    switch (protocol) {
        case NavProtocol::Nmea:
            split_nmea(log, options);
            break;
        case NavProtocol::Novatel: {
            novatel::NovatelDecoder d;
            split_binary(log, d);
            break;
        }
        case NavProtocol::Ncom: {
            ncom::NcomDecoder d;
            split_binary(log, d);
            break;
        }
        default:
            break;
    }
    fill_times(log.messages);
    log.stats.messages = log.messages.size();
    return log;
}

navpose::NavFrame parse_nav_origin(const std::string& spec) {
    std::vector<double> v;
    std::stringstream ss(spec);
    std::string item;
    while (std::getline(ss, item, ',')) {
        try {
            std::size_t used = 0;
            const double x = std::stod(item, &used);
            if (used != item.size() || !std::isfinite(x)) throw std::invalid_argument(item);
            v.push_back(x);
        } catch (const std::exception&) {
            throw ConfigError("--nav-origin '" + spec + "': '" + item + "' is not a number");
        }
    }
    if (v.size() != 3 || std::abs(v[0]) > 90.0 || std::abs(v[1]) > 180.0)
        throw ConfigError("--nav-origin '" + spec +
                          "': expected lat,lon,h (degrees, degrees, metres above the ellipsoid)");
    return navpose::NavFrame::tangent_plane(v[0], v[1], v[2]);
}

std::string nav_log_summary(const NavLog& log) {
    const auto& s = log.stats;
    const auto& d = s.decode;
    std::string out = fmt::format(
        "nav log '{}' ({}): {} bytes, {} {}, {} timed samples ({} without time); skipped: {} "
        "bad checksum, {} truncated, {} invalid fields, {} garbage bytes, {} unsupported",
        log.path, to_string(log.protocol), s.bytes, s.messages,
        is_can(log.protocol) ? "frames" : "messages", s.samples - s.untimed_samples,
        s.untimed_samples, d.bad_checksum, d.truncated, d.invalid_field, d.garbage_bytes,
        d.unsupported);
    if (is_can(log.protocol))
        out +=
            fmt::format(", {} malformed candump lines", s.candump.rejected()) +
            (s.candump.first_bad_line ? fmt::format(" (first: line {})", s.candump.first_bad_line)
                                      : std::string());
    if (s.nmea_date_assumed) out += "; no RMC/ZDA in the log: the host's date was assumed";
    return out;
}

}  // namespace mirage::navproto
