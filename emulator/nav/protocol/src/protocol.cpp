// SPDX-License-Identifier: Apache-2.0
#include "mirage/navproto/protocol.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "mirage/core/error.hpp"
#include "mirage/dis/dis_sample.hpp"
#include "mirage/dis/entity_state.hpp"
#include "mirage/navcan/oxts_can.hpp"
#include "mirage/navcan/sbg_can.hpp"
#include "mirage/ncom/decoder.hpp"
#include "mirage/ncom/encoder.hpp"
#include "mirage/nmea/fields.hpp"
#include "mirage/nmea/nmea_decoder.hpp"
#include "mirage/nmea/nmea_encoder.hpp"
#include "mirage/novatel/decoder.hpp"
#include "mirage/novatel/encoder.hpp"

namespace mirage::navproto {
namespace {

// Decoders for byte protocols ignore CAN frames and vice versa (counted as unsupported).
template <class D>
class ByteAdapter : public NavDecoder {
  public:
    D& decoder() { return d_; }
    void feed_bytes(std::span<const std::uint8_t> b, const nav::SampleFn& fn) override {
        d_.feed(b, fn);
    }
    // NCOM knows datagrams (several whole packets); the others read them as bytes.
    void feed_datagram(std::span<const std::uint8_t> b, const nav::SampleFn& fn) override {
        if constexpr (requires { d_.feed_datagram(b, fn); })
            d_.feed_datagram(b, fn);
        else
            d_.feed(b, fn);
    }
    void feed_frame(const nav::CanFrame&, const nav::SampleFn&) override { ++other_; }
    nav::DecodeCounters counters() const override {
        auto c = d_.counters();
        c.unsupported += other_;
        return c;
    }

  private:
    D d_;
    std::uint64_t other_ = 0;
};

template <class D>
class CanAdapter : public NavDecoder {
  public:
    void feed_bytes(std::span<const std::uint8_t> b, const nav::SampleFn&) override {
        other_ += b.size();
    }
    void feed_frame(const nav::CanFrame& f, const nav::SampleFn& fn) override { d_.feed(f, fn); }
    nav::DecodeCounters counters() const override {
        auto c = d_.counters();
        c.garbage_bytes += other_;
        return c;
    }

  private:
    D d_;
    std::uint64_t other_ = 0;
};

// DIS: one Entity State PDU per datagram, followed by dead reckoning between them.
class DisAdapter : public NavDecoder {
  public:
    DisAdapter(const dis::TrackConfig& c, UtcClock clock) : track_(c), clock_(std::move(clock)) {}
    void feed_bytes(std::span<const std::uint8_t> b, const nav::SampleFn&) override {
        other_bytes_ += b.size();  // a byte stream has no PDU boundaries
    }
    void feed_datagram(std::span<const std::uint8_t> d, const nav::SampleFn& fn) override {
        track_.feed(d, clock_(), fn);
    }
    void feed_frame(const nav::CanFrame&, const nav::SampleFn&) override { ++other_frames_; }
    void tick(const nav::SampleFn& fn) override { track_.tick(clock_(), fn); }
    std::optional<core::Nanos> tick_period() const override { return track_.step(); }
    nav::DecodeCounters counters() const override {
        nav::DecodeCounters c = track_.counters();
        const dis::DisCounters& d = track_.dis_counters();
        c.unsupported += other_frames_ + d.other_pdu + d.other_exercise + d.other_entity;
        c.garbage_bytes += other_bytes_;
        return c;
    }
    std::string detail() const override {
        const auto e = track_.entity();
        const dis::DisCounters& d = track_.dis_counters();
        const dis::TrackCounters& t = track_.track_counters();
        return fmt::format(
            "dis entity {}, PDUs {}, out of order {}, timeouts {}, other entities {}, "
            "other exercises {}, other PDUs {}",
            e ? fmt::format("{}.{}.{}", e->site, e->application, e->entity) : "(none yet)",
            t.accepted, t.out_of_order, t.timeouts, d.other_entity, d.other_exercise, d.other_pdu);
    }

  private:
    dis::EntityTrack track_;
    UtcClock clock_;
    std::uint64_t other_bytes_ = 0, other_frames_ = 0;
};

// One PDU of entity 1.1.1 in exercise 1 per epoch (docs/dis.md §6).
class DisEncoder : public NavEncoder {
  public:
    std::vector<std::uint8_t> encode_bytes(const nav::NavSample& s, std::uint64_t) override {
        return dis::encode(dis::from_sample(s, {1, 1, 1}, 1));
    }
    std::vector<nav::CanFrame> encode_frames(const nav::NavSample&, std::uint64_t) override {
        return {};
    }
};

core::GpsTime host_utc_now() {
    return core::gps_from_unix_ns(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                      std::chrono::system_clock::now().time_since_epoch())
                                      .count());
}

std::vector<std::uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

// Every epoch: GGA (position) and PASHR (attitude), as the OxTS RT of rst39.log does; RMC, ZDA
// and HDT once a second (the date and a heading for plain GNSS clients).
class NmeaEncoder : public NavEncoder {
  public:
    explicit NmeaEncoder(double rate_hz)
        : every_(std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::lround(rate_hz)))) {}
    std::vector<std::uint8_t> encode_bytes(const nav::NavSample& s, std::uint64_t epoch) override {
        std::uint32_t which = nmea::kGga | nmea::kPashr;
        if (epoch % every_ == 0) which |= nmea::kRmc | nmea::kZda | nmea::kHdt;
        return bytes_of(nmea::encode_epoch(s, which));
    }
    std::vector<nav::CanFrame> encode_frames(const nav::NavSample&, std::uint64_t) override {
        return {};
    }

  private:
    std::uint64_t every_;
};

// INSPVAS every epoch (the short-header log a SPAN system streams at high rate), BESTPOS once a
// second.
class NovatelEncoderAdapter : public NavEncoder {
  public:
    explicit NovatelEncoderAdapter(double rate_hz)
        : every_(std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::lround(rate_hz)))) {}
    std::vector<std::uint8_t> encode_bytes(const nav::NavSample& s, std::uint64_t epoch) override {
        std::vector<std::uint8_t> out = e_.inspvas(s);
        if (epoch % every_ == 0) {
            const auto b = e_.bestpos(s);
            out.insert(out.end(), b.begin(), b.end());
        }
        return out;
    }
    std::vector<nav::CanFrame> encode_frames(const nav::NavSample&, std::uint64_t) override {
        return {};
    }

  private:
    novatel::NovatelEncoder e_;
    std::uint64_t every_;
};

class NcomEncoderAdapter : public NavEncoder {
  public:
    std::vector<std::uint8_t> encode_bytes(const nav::NavSample& s, std::uint64_t) override {
        const auto p = e_.encode(s);
        return {p.begin(), p.end()};
    }
    std::vector<nav::CanFrame> encode_frames(const nav::NavSample&, std::uint64_t) override {
        return {};
    }

  private:
    ncom::NcomEncoder e_;
};

class OxtsCanEncoderAdapter : public NavEncoder {
  public:
    std::vector<std::uint8_t> encode_bytes(const nav::NavSample&, std::uint64_t) override {
        return {};
    }
    std::vector<nav::CanFrame> encode_frames(const nav::NavSample& s, std::uint64_t) override {
        return navcan::oxts_can_encode(s);
    }
};

// UTC_0 + UTC_1 once a second (the device-time mapping), the EKF group every epoch.
class SbgCanEncoderAdapter : public NavEncoder {
  public:
    explicit SbgCanEncoderAdapter(double rate_hz)
        : every_(std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::lround(rate_hz)))) {}
    std::vector<std::uint8_t> encode_bytes(const nav::NavSample&, std::uint64_t) override {
        return {};
    }
    std::vector<nav::CanFrame> encode_frames(const nav::NavSample& s,
                                             std::uint64_t epoch) override {
        if (epoch == 0) cfg_.boot = s.t - std::chrono::seconds(1);
        std::vector<nav::CanFrame> out;
        if (epoch % every_ == 0) out = navcan::sbg_can_encode_utc(s.t, cfg_);
        const auto f = navcan::sbg_can_encode(s, cfg_);
        out.insert(out.end(), f.begin(), f.end());
        return out;
    }

  private:
    navcan::SbgCanEncoderConfig cfg_;
    std::uint64_t every_;
};

}  // namespace

NavProtocol parse_nav_protocol(const std::string& name) {
    if (name == "nmea") return NavProtocol::Nmea;
    if (name == "novatel") return NavProtocol::Novatel;
    if (name == "ncom") return NavProtocol::Ncom;
    if (name == "oxts-can") return NavProtocol::OxtsCan;
    if (name == "sbg-can") return NavProtocol::SbgCan;
    if (name == "dis") return NavProtocol::Dis;
    throw ConfigError("nav: unknown protocol '" + name +
                      "' (nmea, novatel, ncom, oxts-can, sbg-can, dis)");
}

std::string to_string(NavProtocol p) {
    switch (p) {
        case NavProtocol::Nmea:
            return "nmea";
        case NavProtocol::Novatel:
            return "novatel";
        case NavProtocol::Ncom:
            return "ncom";
        case NavProtocol::OxtsCan:
            return "oxts-can";
        case NavProtocol::SbgCan:
            return "sbg-can";
        case NavProtocol::Dis:
            return "dis";
    }
    return "?";
}

NavUri parse_nav_uri(const std::string& uri) {
    const auto colon = uri.find(':');
    if (colon == std::string::npos || colon + 1 >= uri.size())
        throw ConfigError("nav URI '" + uri +
                          "': expected <protocol>:<transport>, e.g. nmea:/dev/ttyUSB0?baud=115200");
    NavUri u;
    u.protocol = parse_nav_protocol(uri.substr(0, colon));
    u.transport = uri.substr(colon + 1);
    return u;
}

// Until the first RMC/ZDA: the host's UTC date for live input (the decoder corrects a midnight
// on either side by the time of day), none for a recorded log, or a given date.
std::optional<nmea::Date> nmea_date_hint(const std::string& spec) {
    if (spec == "host") {
        const auto unix_s = std::chrono::duration_cast<std::chrono::seconds>(
                                std::chrono::system_clock::now().time_since_epoch())
                                .count();
        return nmea::Date::from_unix_days(unix_s / 86'400);
    }
    if (spec == "stream") return std::nullopt;
    int y = 0, m = 0, d = 0;
    char tail = 0;
    if (std::sscanf(spec.c_str(), "%4d-%2d-%2d%c", &y, &m, &d, &tail) == 3)
        if (const auto date = nmea::make_date(y, m, d)) return *date;
    throw ConfigError("nav: NMEA date '" + spec + "': expected host, stream or YYYY-MM-DD");
}

std::unique_ptr<NavDecoder> make_nav_decoder(NavProtocol p, const std::string& nmea_date) {
    switch (p) {
        case NavProtocol::Nmea: {
            auto a = std::make_unique<ByteAdapter<nmea::NmeaDecoder>>();
            if (const auto hint = nmea_date_hint(nmea_date)) a->decoder().set_date_hint(*hint);
            return a;
        }
        case NavProtocol::Novatel:
            return std::make_unique<ByteAdapter<novatel::NovatelDecoder>>();
        case NavProtocol::Ncom:
            return std::make_unique<ByteAdapter<ncom::NcomDecoder>>();
        case NavProtocol::OxtsCan:
            return std::make_unique<CanAdapter<navcan::OxtsCanDecoder>>();
        case NavProtocol::SbgCan:
            return std::make_unique<CanAdapter<navcan::SbgCanDecoder>>();
        case NavProtocol::Dis:
            return make_dis_decoder({});
    }
    throw ConfigError("nav: no decoder");
}

std::unique_ptr<NavDecoder> make_dis_decoder(const dis::TrackConfig& config, UtcClock utc_now) {
    return std::make_unique<DisAdapter>(config, utc_now ? std::move(utc_now) : host_utc_now);
}

std::unique_ptr<NavEncoder> make_nav_encoder(NavProtocol p, double rate_hz) {
    switch (p) {
        case NavProtocol::Nmea:
            return std::make_unique<NmeaEncoder>(rate_hz);
        case NavProtocol::Novatel:
            return std::make_unique<NovatelEncoderAdapter>(rate_hz);
        case NavProtocol::Ncom:
            return std::make_unique<NcomEncoderAdapter>();
        case NavProtocol::OxtsCan:
            return std::make_unique<OxtsCanEncoderAdapter>();
        case NavProtocol::SbgCan:
            return std::make_unique<SbgCanEncoderAdapter>(rate_hz);
        case NavProtocol::Dis:
            return std::make_unique<DisEncoder>();
    }
    throw ConfigError("nav: no encoder");
}

}  // namespace mirage::navproto
