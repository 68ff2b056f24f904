// SPDX-License-Identifier: Apache-2.0
#include "mirage/nmea/nmea_decoder.hpp"

#include <cmath>
#include <numbers>

#include "mirage/core/time.hpp"
#include "mirage/nmea/fields.hpp"
#include "mirage/nmea/sentence.hpp"
#include "mirage/nmea/sentences.hpp"

namespace mirage::nmea {
namespace {

using nav::FixQuality;
using nav::NavSample;

constexpr std::int64_t kHalfDayNs = 12 * 3600 * core::kNsPerSecond;
constexpr double kDegToRad = std::numbers::pi / 180.0;

// Degrees clockwise from true north (any sign) -> radians in [0, 2π).
double heading_rad_from_deg(double deg) {
    double d = std::fmod(deg, 360.0);
    if (d < 0.0) d += 360.0;
    const double r = d * kDegToRad;
    return r >= 2.0 * std::numbers::pi ? 0.0 : r;
}

FixQuality gga_quality(int q) {
    switch (q) {
        case 0:
            return FixQuality::None;
        case 1:
            return FixQuality::Autonomous;
        case 2:
        case 3:
            return FixQuality::Differential;  // 3 = PPS (precise) service
        case 4:
            return FixQuality::RtkFixed;
        case 5:
            return FixQuality::RtkFloat;
        case 6:
            return FixQuality::DeadReckoning;
        case 8:
            return FixQuality::Simulated;
        default:
            return FixQuality::Unknown;  // 7 = manual input
    }
}

// FAA mode letter of RMC (NMEA 2.3+).
FixQuality faa_quality(char mode) {
    switch (mode) {
        case 'A':
            return FixQuality::Autonomous;
        case 'D':
            return FixQuality::Differential;
        case 'P':
            return FixQuality::Differential;  // precise
        case 'R':
            return FixQuality::RtkFixed;
        case 'F':
            return FixQuality::RtkFloat;
        case 'E':
            return FixQuality::DeadReckoning;
        case 'S':
            return FixQuality::Simulated;
        case 'N':
            return FixQuality::None;
        default:
            return FixQuality::Unknown;  // absent, 'M' manual, others
    }
}

// Trimble AVR quality: 0 invalid, 1 autonomous, 2 RTK float, 3 RTK fixed, 4 DGPS.
FixQuality avr_quality(int q) {
    switch (q) {
        case 0:
            return FixQuality::None;
        case 1:
            return FixQuality::Autonomous;
        case 2:
            return FixQuality::RtkFloat;
        case 3:
            return FixQuality::RtkFixed;
        default:
            return FixQuality::Differential;
    }
}

Eigen::Vector3d ned_from_course(double speed_knots, double track_deg) {
    const double v = speed_knots * kKnotMps;
    const double c = track_deg * kDegToRad;
    return {v * std::cos(c), v * std::sin(c), 0.0};
}

bool is_eol(std::uint8_t b) { return b == '\r' || b == '\n'; }

// A sentence runs from `$` to its line end; its longest text (without CR LF) is
// kMaxSentenceBytes − 2 bytes.
constexpr std::size_t kMaxLine = kMaxSentenceBytes - 2;

NavSample make_sample(std::uint32_t fields, std::int64_t gps_ns) {
    NavSample s;
    s.source = nav::Protocol::Nmea;
    s.fields = fields;
    s.t = core::GpsTime{core::Nanos{gps_ns}};
    return s;
}

}  // namespace

void NmeaDecoder::set_date_hint(const Date& date) {
    if (date_from_stream_) return;
    date_days_ = date.unix_days();
    have_tod_ = false;
}

void NmeaDecoder::feed(std::string_view text, const nav::SampleFn& on_sample) {
    feed(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()),
                                       text.size()),
         on_sample);
}

void NmeaDecoder::feed(std::span<const std::uint8_t> bytes, const nav::SampleFn& on_sample) {
    buf_.append(bytes);
    buf_.drain(
        counters_.garbage_bytes,
        [](std::uint8_t b) {
            if (b == '$') return nav::ByteKind::Sync;
            // Line ends between sentences are not garbage.
            return is_eol(b) ? nav::ByteKind::Filler : nav::ByteKind::Garbage;
        },
        [&](std::span<const std::uint8_t> rest) {
            for (std::size_t i = 1; i < rest.size(); ++i) {
                if (is_eol(rest[i])) return nav::FrameLength::complete(i);
                if (rest[i] == '$') {
                    ++counters_.truncated;  // the next sentence began before this one ended
                    return nav::FrameLength::skip(i, false);
                }
                if (i == kMaxLine) {
                    ++counters_.truncated;  // over-long: the rest up to the next `$` is garbage
                    return nav::FrameLength::skip(i, false);
                }
            }
            return nav::FrameLength::need_more();
        },
        [&](std::span<const std::uint8_t> line) {
            handle_line(std::string_view(reinterpret_cast<const char*>(line.data()), line.size()),
                        on_sample);
            return line.size();
        });
}

std::optional<std::int64_t> NmeaDecoder::time_on_kept_date(const UtcTime& t) {
    if (!date_days_) return std::nullopt;
    const std::int64_t tod = t.ns_of_day();
    std::int64_t day = *date_days_;
    if (have_tod_ && tod < last_tod_ns_ - kHalfDayNs) {
        // Midnight passed since the date was learnt: move the kept date on.
        date_days_ = ++day;
        last_tod_ns_ = tod;
    } else if (have_tod_ && tod > last_tod_ns_ + kHalfDayNs) {
        --day;  // a late sentence from before midnight; the kept date stays
    } else {
        last_tod_ns_ = tod;
        have_tod_ = true;
    }
    return gps_ns_from_utc(Date::from_unix_days(day), t);
}

void NmeaDecoder::set_date(const Date& d, const std::optional<UtcTime>& t) {
    date_days_ = d.unix_days();
    date_from_stream_ = true;
    have_tod_ = t.has_value();
    if (t) last_tod_ns_ = t->ns_of_day();
}

void NmeaDecoder::emit(NavSample& s, const nav::SampleFn& on_sample) {
    if (s.has(NavSample::kTime)) last_time_ns_ = s.t.time_since_epoch().count();
    ++counters_.samples;
    if (on_sample) on_sample(s);
}

// Validation order (decode_counters.hpp): length and sync by the framer, then checksum, tag,
// fields; each line lands in exactly one counter.
void NmeaDecoder::handle_line(std::string_view line, const nav::SampleFn& on_sample) {
    Sentence sen;
    switch (parse_sentence(line, sen)) {
        case FrameStatus::Ok:
            break;
        case FrameStatus::TooLong:
        case FrameStatus::NoSync:
        case FrameStatus::Truncated:
            ++counters_.truncated;
            return;
        case FrameStatus::BadChecksum:
            ++counters_.bad_checksum;
            return;
        case FrameStatus::BadChar:
        case FrameStatus::BadTag:
            ++counters_.invalid_field;
            return;
    }
    ParseStatus st = ParseStatus::Unsupported;
    // The sample to emit, if any: built by the case, emitted once below.
    std::optional<NavSample> out;
    bool no_data = false;
    bool before_date = false;
    // A timed sentence's GPS time on the kept date, or flags why there is none.
    auto timed = [&](const std::optional<UtcTime>& t) -> std::optional<std::int64_t> {
        if (!t) {
            no_data = true;
            return std::nullopt;
        }
        auto g = time_on_kept_date(*t);
        if (!g) before_date = true;
        return g;
    };
    // HDT and VTG have no time: they take the latest timed sentence's.
    auto untimed = [&]() -> std::optional<std::int64_t> {
        if (!date_days_ || !last_time_ns_) {
            before_date = true;
            return std::nullopt;
        }
        return last_time_ns_;
    };

    switch (sen.type) {
        case SentenceType::Gga: {
            Gga g;
            st = parse_gga(sen, g);
            if (st != ParseStatus::Ok) break;
            ++nmea_.gga;
            const auto t = timed(g.time);
            if (!t) break;
            NavSample s = make_sample(NavSample::kTime, *t);
            s.quality = gga_quality(g.quality);
            s.satellites = static_cast<std::uint8_t>(g.satellites.value_or(0));
            // Quality 0 means "fix not valid": a stale position some receivers repeat.
            if (g.quality != 0 && g.lat_deg && g.lon_deg && g.altitude_msl_m) {
                s.fields |= NavSample::kPosition;
                s.lat_deg = *g.lat_deg;
                s.lon_deg = *g.lon_deg;
                // Ellipsoidal height = orthometric (MSL) + geoid separation (GGA fields 9, 11).
                s.height_m = *g.altitude_msl_m + g.geoid_separation_m.value_or(0.0);
                if (!g.geoid_separation_m) s.fields |= NavSample::kHeightIsMsl;
            }
            out = s;
            break;
        }
        case SentenceType::Rmc: {
            Rmc r;
            st = parse_rmc(sen, r);
            if (st != ParseStatus::Ok) break;
            ++nmea_.rmc;
            // The date is taken whatever the status: a receiver without a fix still keeps time.
            if (r.date) set_date(*r.date, r.time);
            const auto t = timed(r.time);
            if (!t) break;
            NavSample s = make_sample(NavSample::kTime, *t);
            s.quality = r.valid ? faa_quality(r.mode) : FixQuality::None;
            if (r.valid && r.speed_knots && r.track_deg) {
                s.fields |= NavSample::kVelocity;
                s.velocity_ned_mps = ned_from_course(*r.speed_knots, *r.track_deg);
            }
            out = s;
            break;
        }
        case SentenceType::Zda: {
            Zda z;
            st = parse_zda(sen, z);
            if (st != ParseStatus::Ok) break;
            ++nmea_.zda;
            if (z.date) set_date(*z.date, z.time);
            const auto t = timed(z.time);
            if (t) out = make_sample(NavSample::kTime, *t);
            break;
        }
        case SentenceType::Pashr: {
            Pashr p;
            st = parse_pashr(sen, p);
            if (st != ParseStatus::Ok) break;
            ++nmea_.pashr;
            const auto t = timed(p.time);
            if (!t) break;
            NavSample s = make_sample(NavSample::kTime, *t);
            if (p.heading_deg && p.roll_deg && p.pitch_deg) {
                // OxTS (RT manual, "heading, pitch, roll" of the vehicle frame x fwd, y right,
                // z down) uses the aerospace convention NavSample uses: roll positive right
                // side down, pitch positive nose up, heading clockwise from true north. gpsd's
                // processPASHR copies fields 4 and 5 unchanged too. So no sign flips here.
                s.fields |= NavSample::kAttitude;
                s.roll_rad = *p.roll_deg * kDegToRad;
                s.pitch_rad = *p.pitch_deg * kDegToRad;
                s.heading_rad = heading_rad_from_deg(*p.heading_deg);
            }
            out = s;
            break;
        }
        case SentenceType::PtnlAvr: {
            PtnlAvr a;
            st = parse_ptnl_avr(sen, a);
            if (st != ParseStatus::Ok) break;
            ++nmea_.ptnl_avr;
            const auto t = timed(a.time);
            if (!t) break;
            NavSample s = make_sample(NavSample::kTime, *t);
            s.quality = avr_quality(a.quality);
            s.satellites = static_cast<std::uint8_t>(a.satellites.value_or(0));
            if (a.yaw_deg) {
                // Yaw of the antenna baseline, clockwise from true north (may be negative);
                // tilt = elevation of the baseline = pitch when antenna 2 is ahead of antenna 1.
                s.fields |= NavSample::kHeading;
                s.heading_rad = heading_rad_from_deg(*a.yaw_deg);
                s.pitch_rad = a.tilt_deg.value_or(0.0) * kDegToRad;
            }
            out = s;
            break;
        }
        case SentenceType::Hdt: {
            Hdt h;
            st = parse_hdt(sen, h);
            if (st != ParseStatus::Ok) break;
            ++nmea_.hdt;
            if (!h.heading_deg) {
                no_data = true;
                break;
            }
            const auto t = untimed();
            if (!t) break;
            NavSample s = make_sample(NavSample::kHeading, *t);
            s.heading_rad = heading_rad_from_deg(*h.heading_deg);
            out = s;
            break;
        }
        case SentenceType::Vtg: {
            Vtg v;
            st = parse_vtg(sen, v);
            if (st != ParseStatus::Ok) break;
            ++nmea_.vtg;
            if (!v.track_deg || !v.speed_knots) {
                no_data = true;
                break;
            }
            const auto t = untimed();
            if (!t) break;
            NavSample s = make_sample(NavSample::kVelocity, *t);
            s.velocity_ned_mps = ned_from_course(*v.speed_knots, *v.track_deg);
            out = s;
            break;
        }
        case SentenceType::Unknown:
            break;
    }

    switch (st) {
        case ParseStatus::Unsupported:
            ++counters_.unsupported;
            return;
        case ParseStatus::InvalidField:
            ++counters_.invalid_field;
            return;
        case ParseStatus::Ok:
            ++counters_.messages_ok;
            break;
    }
    if (no_data) ++nmea_.no_data;
    if (before_date) ++nmea_.before_date;
    if (out) emit(*out, on_sample);
}

}  // namespace mirage::nmea
