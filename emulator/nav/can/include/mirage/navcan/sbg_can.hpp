// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "mirage/nav/can_frame.hpp"
#include "mirage/nav/decode_counters.hpp"
#include "mirage/nav/nav_sample.hpp"

// SBG Systems CAN output (docs/nav-protocols.md §7.2, sbgCan.dbc; Intel byte order).
// Mapping to NavSample: EKF_EULER yaw ±π -> heading [0, 2π) (EKF_QUAT, Q0 = w, body->NED, is
// used when no EKF_EULER came); EKF_ALTITUDE is MSL + undulation -> ellipsoidal height
// (ALTITUDE + UNDULATION, no kHeightIsMsl); EKF_VEL_NED is already N, E, D. Time: frames carry
// the device's µs clock; UTC_0 maps it to GPS time of week (SBG's rule, §4:
// tow = utc.gps_tow + (ts − utc.ts)/1000) and UTC_1's date picks the GPS week.
namespace mirage::navcan {

struct SbgCanIds {
    std::uint32_t status_03 = 0x102;  // SOLUTION status (fix quality, validity bits)
    std::uint32_t utc_0 = 0x110;
    std::uint32_t utc_1 = 0x111;
    std::uint32_t ekf_info = 0x130;
    std::uint32_t ekf_quat = 0x131;
    std::uint32_t ekf_euler = 0x132;
    std::uint32_t ekf_pos = 0x134;
    std::uint32_t ekf_altitude = 0x135;
    std::uint32_t ekf_vel_ned = 0x137;
    bool extended = false;
};

// Grouping rule: EKF_INFO opens a group with its TIME_STAMP; EKF_QUAT/EULER/POS/ALTITUDE/
// VEL_NED frames after it belong to it. The group is emitted as soon as it holds attitude
// (EULER or QUAT), POS, ALTITUDE and VEL_NED, or when the next EKF_INFO with another
// timestamp arrives (then with what it has). A group needs a GPS time mapping (a UTC_0 + UTC_1
// seen before) to become a sample; otherwise it counts in no_time_groups. EKF frames before
// any EKF_INFO count in orphan_frames. STATUS_03, when seen, sets quality and drops fields
// whose valid bit is clear.
class SbgCanDecoder {
  public:
    explicit SbgCanDecoder(SbgCanIds ids = {});

    void feed(const nav::CanFrame& frame, const nav::SampleFn& on_sample);
    void flush(const nav::SampleFn& on_sample);

    const nav::DecodeCounters& counters() const { return counters_; }
    std::uint64_t no_time_groups() const { return no_time_groups_; }
    std::uint64_t orphan_frames() const { return orphan_frames_; }
    // GPS time of a device timestamp through the last UTC mapping; nullopt before one.
    std::optional<core::GpsTime> gps_time_of(std::uint32_t device_us) const;

  private:
    enum Part : std::uint32_t {
        kQuat = 1u << 0,
        kEuler = 1u << 1,
        kPos = 1u << 2,
        kAlt = 1u << 3,
        kVel = 1u << 4,
    };
    void close(const nav::SampleFn& on_sample);

    SbgCanIds ids_;
    // UTC mapping: UTC_0 gives (device ts, tow ms); UTC_1 gives the date that fixes the week.
    bool utc0_pending_ = false;
    std::uint32_t utc0_ts_ = 0;
    std::uint32_t utc0_tow_ms_ = 0;
    bool have_anchor_ = false;
    std::uint32_t anchor_ts_ = 0;
    std::int64_t anchor_gps_ns_ = 0;

    bool group_open_ = false;
    std::uint32_t group_ts_ = 0;
    std::uint32_t parts_ = 0;
    nav::NavSample group_{};
    double quat_[4] = {1, 0, 0, 0};
    double altitude_msl_m_ = 0.0;
    double undulation_m_ = 0.0;

    bool have_status_ = false;
    std::uint32_t solution_status_ = 0;

    nav::DecodeCounters counters_;
    std::uint64_t no_time_groups_ = 0;
    std::uint64_t orphan_frames_ = 0;
};

// Encoder state: a device clock (µs since `boot`, wrapping at 2^32) and the undulation to split
// the ellipsoidal height into SBG's ALTITUDE (MSL) + UNDULATION.
struct SbgCanEncoderConfig {
    SbgCanIds ids;
    core::GpsTime boot{};  // GPS time when the device clock read 0
    double undulation_m = 0.0;
    std::uint32_t solution_status = 0x000008F4;  // full navigation, att/hdg/vel/pos valid, GNSS pos
};

// UTC_0 + UTC_1 for GPS time `t` rounded down to a whole ms (UTC_0's GPS_TOW is in ms); the
// UTC_0 TIME_STAMP is the device time of that ms, so a decoder maps device time exactly.
std::vector<nav::CanFrame> sbg_can_encode_utc(core::GpsTime t, const SbgCanEncoderConfig& cfg);
// STATUS_03 (when its ID is set), EKF_INFO, then EKF_QUAT + EKF_EULER (kAttitude), EKF_POS +
// EKF_ALTITUDE (kPosition), EKF_VEL_NED (kVelocity); EKF_INFO's timestamp is the device time of
// sample.t. Values round to the signal resolution and saturate.
std::vector<nav::CanFrame> sbg_can_encode(const nav::NavSample& sample,
                                          const SbgCanEncoderConfig& cfg);

}  // namespace mirage::navcan
