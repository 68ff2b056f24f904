// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <vector>

#include "mirage/nav/can_frame.hpp"
#include "mirage/nav/decode_counters.hpp"
#include "mirage/nav/nav_sample.hpp"

// OxTS RT CAN navigation messages (docs/nav-protocols.md §7.1; Intel byte order, GPS time).
// Mapping to NavSample: 0x600 DateTime is a GPS-scale calendar time, 0x630 MilliTime is ms
// since the GPS epoch (preferred when both arrive: 1 ms vs 10 ms); 0x602 altitude is MSL by
// default, so samples carry kHeightIsMsl unless `altitude_is_ellipsoidal`; 0x603 velocity is
// already N, E, Down; 0x607 heading is unsigned 0..359.99° -> [0, 2π), pitch/roll ° -> rad;
// 0x605 acceleration (x, y, z m/s²) and 0x608 rate (x, y, z °/s) are vehicle-frame (FRD).
namespace mirage::navcan {

// IDs are configurable per unit (NAVconfig), so every one comes from here; 0 disables one.
struct OxtsCanIds {
    std::uint32_t date_time = 0x600;
    std::uint32_t lat_lon = 0x601;
    std::uint32_t altitude = 0x602;
    std::uint32_t velocity = 0x603;
    std::uint32_t accel_vehicle = 0x605;
    std::uint32_t heading_pitch_roll = 0x607;
    std::uint32_t rate_vehicle = 0x608;
    std::uint32_t milli_time = 0x630;
    bool extended = false;  // 29-bit identifiers
};

struct OxtsCanConfig {
    OxtsCanIds ids;
    bool altitude_is_ellipsoidal = false;  // the unit was set to output ellipsoidal height
    // Stamped frames further apart than this from the group's first frame start a new group.
    std::int64_t max_group_span_ns = 10'000'000;
};

// Grouping rule (one sample per output cycle):
//  - Frames of one cycle collect into an open group, whatever their order on the bus.
//  - A message type that is already in the open group starts the next cycle: the open group is
//    closed first; so does a 0x600/0x630 whose time is not the group's 10 ms cycle (a unit
//    sending in ID order puts 0x630 after 0x607). With stamped frames, a frame more than
//    max_group_span_ns after the group's first frame closes it too.
//  - The group is closed at once when it holds a time (0x600 or 0x630) and every other
//    enabled navigation message (0x601, 0x602, 0x603, 0x607), so a complete cycle costs no
//    extra latency; 0x605/0x608 join only if they arrive before that (otherwise they start a
//    group of their own that ends up in incomplete_groups).
//  - A 0x600/0x630 of the cycle just emitted that arrives before anything else (0x630 after
//    0x607 from a unit sending in ID order) is absorbed into that cycle, not a new group.
//  - A closed group becomes a sample if it has a time and at least one of position (0x601
//    and 0x602), velocity or attitude; otherwise it is counted in incomplete_groups.
// Bad frames (short DLC -> truncated, out-of-range field -> invalid_field) are counted and
// not applied; RTR/error frames and other IDs are `unsupported`.
class OxtsCanDecoder {
  public:
    explicit OxtsCanDecoder(OxtsCanConfig config = {});

    void feed(const nav::CanFrame& frame, const nav::SampleFn& on_sample);
    void feed(const nav::StampedCanFrame& frame, const nav::SampleFn& on_sample);
    // Emits the open group if it qualifies (end of a log).
    void flush(const nav::SampleFn& on_sample);

    const nav::DecodeCounters& counters() const { return counters_; }
    std::uint64_t incomplete_groups() const { return incomplete_groups_; }
    // UtcOffset of the last 0x630 (s; the unit's GPS − UTC figure), 0 before one arrives.
    int utc_offset_s() const { return utc_offset_s_; }

  private:
    enum Part : std::uint32_t {
        kDateTime = 1u << 0,
        kMilliTime = 1u << 1,
        kLatLon = 1u << 2,
        kAlt = 1u << 3,
        kVel = 1u << 4,
        kHpr = 1u << 5,
        kAccel = 1u << 6,
        kRate = 1u << 7,
    };
    bool decode_into(const nav::CanFrame& frame, std::uint32_t& part);
    void close(const nav::SampleFn& on_sample);

    OxtsCanConfig config_;
    std::uint32_t complete_mask_ = 0;
    std::uint32_t parts_ = 0;
    nav::NavSample group_{};
    std::int64_t date_time_ns_ = 0;
    std::int64_t milli_time_ns_ = 0;
    bool group_stamped_ = false;
    std::int64_t group_first_ns_ = 0;
    nav::DecodeCounters counters_;
    std::uint64_t incomplete_groups_ = 0;
    int utc_offset_s_ = 0;
    bool have_emitted_ = false;
    std::int64_t emitted_cycle_ = 0;  // emitted sample's time in 10 ms units
};

// Frames for one sample: 0x600 and 0x630 when kTime, 0x601+0x602 when kPosition, 0x603 when
// kVelocity, 0x605 / 0x608 when kAcceleration / kAngularRate, and 0x607 last when kAttitude
// (kHeading alone gives pitch = roll = 0), each only when its ID is non-zero. Values round to the
// signal resolution and saturate at the signal range. Height is written as is: the caller
// decides whether it is MSL (the unit's default) by what it puts in height_m.
// `utc_offset_s` fills 0x630's UtcOffset as given (the decoder reports it back unchanged).
std::vector<nav::CanFrame> oxts_can_encode(const nav::NavSample& sample, const OxtsCanIds& ids = {},
                                           int utc_offset_s = 18);

}  // namespace mirage::navcan
