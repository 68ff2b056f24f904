// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "mirage/core/time.hpp"
#include "mirage/velodyne/model.hpp"

namespace mirage::velodyne {

// docs/wire-formats.md §1.1 / §1.9.
inline constexpr std::size_t kPositionPacketSize = 512;
inline constexpr std::uint16_t kDataPort = 2368;
inline constexpr std::uint16_t kPositionPort = 8308;
inline constexpr std::size_t kPositionTimestampOffset = 198;
inline constexpr std::size_t kPpsOffset = 202;
inline constexpr std::size_t kNmeaOffset = 206;

// Byte 202 (VLP-16, VLP-32C layouts).
enum class PpsStatus : std::uint8_t { Absent = 0, Synchronizing = 1, Locked = 2, Error = 3 };

// What the GPS receiver reports (WGS84 degrees; speed over ground and course for $GPRMC).
struct GeoFix {
    double lat_deg = 0;
    double lon_deg = 0;
    double speed_knots = 0;
    double course_deg = 0;
    bool valid = true;  // 'A' (valid) or 'V' (warning) in the sentence
};

// NMEA checksum: XOR of the characters strictly between '$' and '*' (or of all of `body` when
// it has neither).
std::uint8_t nmea_checksum(std::string_view body);
// "$GPRMC,hhmmss,A,ddmm.mmmm,N,dddmm.mmmm,E,sss.s,ccc.c,ddmmyy,,,A*hh" (no CR LF) at the UTC
// second of t (the receiver's last 1 Hz fix).
std::string gprmc_sentence(core::GpsTime t, const GeoFix& fix);

// HDL-32E IMU words (§1.9 c), already scaled to the device's 12-bit counts; zero by default.
struct Hdl32eImuWords {
    std::array<std::int16_t, 3> gyro{}, temperature{}, accel_x{}, accel_y{};
};

struct PositionPacketOptions {
    PpsStatus pps = PpsStatus::Locked;
    Hdl32eImuWords imu{};
};

// Writes the 512-byte position packet of `layout` (not None) for time t: timestamp on the data
// packets' clock, PPS byte (VLP-16 / VLP-32C), $GPRMC + CR LF at 206, zero padding.
void encode_position(PositionLayout layout, core::GpsTime t, const GeoFix& fix,
                     const PositionPacketOptions& opt,
                     std::span<std::uint8_t, kPositionPacketSize> out);

enum class PositionStatus : std::uint8_t {
    Ok,
    WrongSize,     // not 512 bytes
    NoSentence,    // no '$' at byte 206
    Unterminated,  // no "*hh" before the end of the packet
    BadChecksum,   // hh differs from the XOR of the sentence
    BadTimestamp,  // ≥ 3 600 000 000 µs
};
inline constexpr std::size_t kPositionStatusCount = 6;
const char* to_string(PositionStatus s);

struct PositionCounters {
    std::array<std::uint64_t, kPositionStatusCount> count{};
    void add(PositionStatus s) { ++count[static_cast<std::size_t>(s)]; }
    std::uint64_t operator[](PositionStatus s) const { return count[static_cast<std::size_t>(s)]; }
    std::uint64_t total() const;
};

struct DecodedPosition {
    std::uint32_t timestamp_us = 0;
    std::uint8_t pps = 0;
    std::string sentence;  // "$...*hh", without CR LF
    // Parsed $xxRMC fields (rmc false for other sentences or unparsable fields).
    bool rmc = false;
    bool fix_valid = false;
    int hour = 0, minute = 0, second = 0, day = 0, month = 0, year = 0;  // year 4 digits
    double lat_deg = 0, lon_deg = 0;
};

// Never throws (beyond std::bad_alloc for the sentence), never reads outside `bytes`.
PositionStatus decode_position(std::span<const std::uint8_t> bytes, DecodedPosition& out);

}  // namespace mirage::velodyne
