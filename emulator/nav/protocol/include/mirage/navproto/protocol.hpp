// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "mirage/core/time.hpp"
#include "mirage/dis/entity_track.hpp"
#include "mirage/nav/can_frame.hpp"
#include "mirage/nav/decode_counters.hpp"
#include "mirage/nav/nav_sample.hpp"
#include "mirage/nmea/fields.hpp"

namespace mirage::navproto {

// The navigation protocols `mirage live` reads and `mirage fake-ins` writes.
enum class NavProtocol : std::uint8_t { Nmea, Novatel, Ncom, OxtsCan, SbgCan, Dis };

NavProtocol parse_nav_protocol(const std::string& name);  // throws ConfigError
std::string to_string(NavProtocol p);
inline bool is_can(NavProtocol p) { return p == NavProtocol::OxtsCan || p == NavProtocol::SbgCan; }
// Protocols whose messages are whole UDP datagrams only (DIS PDUs).
inline bool needs_datagrams(NavProtocol p) { return p == NavProtocol::Dis; }

// `--nav` URI: "<protocol>:<transport>", e.g. nmea:/dev/ttyUSB0?baud=115200,
// novatel:tcp://host:port, ncom:udp://:3000, oxts-can:socketcan:can0, sbg-can:slcan:/dev/ttyACM0,
// oxts-can:gsusb:1d50:606f, oxts-can:memory:bench.
struct NavUri {
    NavProtocol protocol = NavProtocol::Nmea;
    std::string transport;  // a ByteStream URI, or a CanBus spec for the CAN protocols
};
NavUri parse_nav_uri(const std::string& uri);  // throws ConfigError naming the URI

// One protocol's incremental decoder behind one interface: bytes (serial, TCP), whole datagrams
// (UDP) or CAN frames.
class NavDecoder {
  public:
    virtual ~NavDecoder() = default;
    virtual void feed_bytes(std::span<const std::uint8_t> bytes, const nav::SampleFn& fn) = 0;
    virtual void feed_datagram(std::span<const std::uint8_t> datagram, const nav::SampleFn& fn) {
        feed_bytes(datagram, fn);
    }
    virtual void feed_frame(const nav::CanFrame& frame, const nav::SampleFn& fn) = 0;
    // Sources that compute samples between messages (DIS dead reckoning): called after every
    // read, and reads wait at most tick_period() so it runs that often.
    virtual void tick(const nav::SampleFn&) {}
    virtual std::optional<core::Nanos> tick_period() const { return std::nullopt; }
    virtual nav::DecodeCounters counters() const = 0;
    // What the protocol adds to the counters, for status lines ("" when nothing).
    virtual std::string detail() const { return {}; }
};
// `nmea_date`: the UTC date NMEA sentences are dated with until an RMC or ZDA gives one —
// "host" (the host's date: live input), "stream" (none: sentences before the first date are
// dropped; recorded logs of another day) or "YYYY-MM-DD". Throws ConfigError otherwise.
std::unique_ptr<NavDecoder> make_nav_decoder(NavProtocol p, const std::string& nmea_date = "host");
// The DIS source (docs/dis.md §6) with its filter and timeout; `utc_now` reads the host's UTC
// clock as GPS time (default: CLOCK_REALTIME), which absolute timestamps are placed against and
// dead reckoning runs on.
using UtcClock = std::function<core::GpsTime()>;
std::unique_ptr<NavDecoder> make_dis_decoder(const dis::TrackConfig& config, UtcClock utc_now = {});
// The date hint of such a spec (nullopt for "stream"). Throws ConfigError on anything else.
std::optional<nmea::Date> nmea_date_hint(const std::string& spec);

// The fake INS's encoder: one epoch of a perfect INS (`s` has time, position, attitude,
// velocity) as the bytes or CAN frames the protocol sends for it. `epoch` counts from 0 so
// encoders can send slower messages every n-th epoch (e.g. NMEA RMC/ZDA at 1 Hz).
class NavEncoder {
  public:
    virtual ~NavEncoder() = default;
    virtual std::vector<std::uint8_t> encode_bytes(const nav::NavSample& s,
                                                   std::uint64_t epoch) = 0;
    virtual std::vector<nav::CanFrame> encode_frames(const nav::NavSample& s,
                                                     std::uint64_t epoch) = 0;
};
// `rate_hz`: the epoch rate, so 1 Hz messages can be spaced.
std::unique_ptr<NavEncoder> make_nav_encoder(NavProtocol p, double rate_hz);

}  // namespace mirage::navproto
