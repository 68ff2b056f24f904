// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace mirage::ncom {

inline constexpr std::size_t kPacketSize = 72;
inline constexpr std::uint8_t kSync = 0xE7;
inline constexpr std::int32_t kInvalidI24 = -0x800000;  // raw 0x800000: field invalid
inline constexpr std::int32_t kMaxI24 = 0x7FFFFF;
inline constexpr std::uint16_t kUdpPort = 3000;
inline constexpr std::int32_t kMsPerMinute = 60'000;

// Scales of the i24 fields (§3).
inline constexpr double kAccelScale = 1e-4;  // m/s²
inline constexpr double kRateScale = 1e-5;   // rad/s
inline constexpr double kVelScale = 1e-4;    // m/s
inline constexpr double kAngleScale = 1e-6;  // rad

// Byte 21.
enum NavStatus : std::uint8_t {
    kNavNothing = 0,
    kNavRawImu = 1,
    kNavInitialising = 2,
    kNavLocking = 3,
    kNavLocked = 4,
    kNavUnlocked = 5,
    kNavExpired = 6,
    kNavStatusOnly = 10,
    kNavTriggerInit = 20,
    kNavTriggerLocking = 21,
    kNavTriggerLocked = 22,
};

// Position/velocity/orientation modes of status channel 0 (OxTS NCOM manual; 0-6 also in the
// OxTS decoder's enum).
enum GnssMode : std::uint8_t {
    kModeNone = 0,
    kModeSearch = 1,
    kModeDoppler = 2,
    kModeSps = 3,
    kModeDifferential = 4,
    kModeRtkFloat = 5,
    kModeRtkInteger = 6,
    kModeWaas = 7,
    kModeOmnistar = 8,
    kModeOmnistarHp = 9,
    kModeNoData = 10,
    kModeBlanked = 11,
    kModeDopplerPp = 12,
    kModeSpsPp = 13,
    kModeDifferentialPp = 14,
    kModeRtkFloatPp = 15,
    kModeRtkIntegerPp = 16,
    kModeOmnistarXp = 17,
    kModeCdgps = 18,
    kModeNotRecognised = 19,
    kModeGxDoppler = 20,
    kModeGxSps = 21,
    kModeGxDifferential = 22,
    kModeGxFloat = 23,
    kModeGxInteger = 24,
};

// One packet in protocol units (raw i24 counts, radians, GPS ms into the minute).
struct Packet {
    std::uint16_t ms_of_minute = 0;
    std::array<std::int32_t, 3> accel{};  // × kAccelScale, vehicle x (fwd), y (right), z (down)
    std::array<std::int32_t, 3> rate{};   // × kRateScale
    std::uint8_t nav_status = kNavNothing;
    double lat_rad = 0.0;
    double lon_rad = 0.0;
    float alt_m = 0.0F;
    std::array<std::int32_t, 3> vel_ned{};  // × kVelScale
    std::int32_t heading = 0;               // × kAngleScale
    std::int32_t pitch = 0;
    std::int32_t roll = 0;
    std::uint8_t channel = 0;
    std::array<std::uint8_t, 8> status{};
};

// Status channel 0: GPS minutes since 1980-01-06, satellites, GNSS modes.
struct Channel0 {
    std::int32_t gps_minutes = 0;
    std::uint8_t satellites = 0;
    std::uint8_t position_mode = kModeNone;
    std::uint8_t velocity_mode = kModeNone;
    std::uint8_t orientation_mode = 0x80;  // dual antenna: bit 7 set = invalid
};

// Checksum n (1, 2, 3) = Σ bytes 1..{21, 60, 70} mod 256, stored at byte {22, 61, 71}.
std::uint8_t checksum(std::span<const std::uint8_t, kPacketSize> p, int which);
// All three checksums match.
bool checksums_ok(std::span<const std::uint8_t, kPacketSize> p);

// Sync and all three checksums are filled in.
std::array<std::uint8_t, kPacketSize> pack(const Packet& p);
// Field extraction only: no sync or checksum check.
Packet unpack(std::span<const std::uint8_t, kPacketSize> bytes);

std::array<std::uint8_t, 8> pack_channel0(const Channel0& c);
Channel0 unpack_channel0(const std::array<std::uint8_t, 8>& payload);

// 24-bit two's complement, little-endian.
std::int32_t read_i24(const std::uint8_t* p);
void write_i24(std::uint8_t* p, std::int32_t v);
// value / scale rounded to nearest, clamped to ±kMaxI24 (never the invalid marker); NaN/Inf ->
// kInvalidI24.
std::int32_t quantise_i24(double value, double scale);

}  // namespace mirage::ncom
