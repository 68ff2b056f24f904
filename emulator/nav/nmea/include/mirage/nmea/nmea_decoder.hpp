// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "mirage/nav/decode_counters.hpp"
#include "mirage/nav/nav_sample.hpp"
#include "mirage/nav/resync_buffer.hpp"
#include "mirage/nmea/fields.hpp"
#include "mirage/nmea/sentence.hpp"

namespace mirage::nmea {

// Per-sentence-type tallies on top of nav::DecodeCounters.
struct NmeaCounters {
    std::uint64_t gga = 0, rmc = 0, vtg = 0, hdt = 0, zda = 0, pashr = 0, ptnl_avr = 0;
    std::uint64_t before_date = 0;  // valid sentences dropped because no date was known yet
    std::uint64_t no_data = 0;      // valid sentences whose data fields were all empty
};

// Incremental NMEA 0183 decoder: feed() any split of the byte stream; it resynchronises on `$`,
// never throws and counts what it drops. What each sentence yields (all in NavSample
// conventions; UTC converted to GPS time with the leap-second table):
//  - GGA: kTime (+ kPosition when quality > 0 and lat, lon, altitude are present). Height = MSL +
//  geoid
//    separation (ellipsoidal); with the separation empty, height = MSL and kHeightIsMsl.
//    Quality 0 None, 1 Autonomous, 2/3 Differential, 4 RtkFixed, 5 RtkFloat,
//    6 DeadReckoning, 7 Unknown (manual input), 8 Simulated; satellites.
//  - RMC: kTime (it sets the date), + kVelocity when status is A and speed and track are
//    present: NED from speed over ground and true track, down = 0 (NMEA has no vertical
//    speed). RMC lat/lon are not reported: NavSample has no "position without height" form
//    and GGA of the same epoch carries them with height. Quality from the FAA mode letter.
//  - ZDA: kTime (it sets the date).
//  - PASHR (OxTS): kTime | kAttitude; see nmea_decoder.cpp for the roll/pitch sign mapping.
//  - PTNL,AVR: kTime | kHeading from yaw; pitch_rad carries the tilt (not flagged: no field
//    bit means "heading and pitch"), quality and satellites from the sentence.
//  - HDT: kHeading; VTG: kVelocity. These carry no time: t is the time of the latest timed
//    sentence and kTime is NOT set.
// No sample is emitted before a date is known (from RMC/ZDA or set_date_hint); such sentences
// are counted in NmeaCounters::before_date. A time of day more than 12 h before the last one
// means midnight passed: the kept date advances by one day (and 12 h after: the previous day).
class NmeaDecoder {
  public:
    // Date to assume until an RMC or ZDA gives one; ignored once a date has been seen.
    void set_date_hint(const Date& date);
    bool has_date() const { return date_days_.has_value(); }

    void feed(std::span<const std::uint8_t> bytes, const nav::SampleFn& on_sample);
    void feed(std::string_view text, const nav::SampleFn& on_sample);

    const nav::DecodeCounters& counters() const { return counters_; }
    const NmeaCounters& nmea_counters() const { return nmea_; }

  private:
    void handle_line(std::string_view line, const nav::SampleFn& on_sample);
    // GPS time of a time of day on the kept date (midnight roll handled); nullopt without a date.
    std::optional<std::int64_t> time_on_kept_date(const UtcTime& t);
    void set_date(const Date& d, const std::optional<UtcTime>& t);
    void emit(nav::NavSample& s, const nav::SampleFn& on_sample);

    nav::ResyncBuffer buf_{kMaxSentenceBytes};
    std::optional<std::int64_t> date_days_;  // kept UTC date (days since 1970-01-01)
    bool date_from_stream_ = false;
    bool have_tod_ = false;
    std::int64_t last_tod_ns_ = 0;  // time of day of the latest timed sentence on the kept date
    std::optional<std::int64_t> last_time_ns_;  // GPS ns of the latest timed sentence
    nav::DecodeCounters counters_;
    NmeaCounters nmea_;
};

}  // namespace mirage::nmea
