// SPDX-License-Identifier: Apache-2.0
#include "mirage/ncom/packet.hpp"

#include <bit>
#include <cmath>
#include <cstring>

namespace mirage::ncom {
namespace {

// Checksum n covers bytes 1..end-1 and is stored at `end` (§3).
constexpr std::size_t kChecksumAt[3] = {22, 61, 71};

std::uint32_t get_u32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
           (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
void put_u32(std::uint8_t* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint64_t get_u64(const std::uint8_t* p) {
    return static_cast<std::uint64_t>(get_u32(p)) |
           (static_cast<std::uint64_t>(get_u32(p + 4)) << 32);
}
void put_u64(std::uint8_t* p, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

}  // namespace

std::int32_t read_i24(const std::uint8_t* p) {
    const std::uint32_t u = static_cast<std::uint32_t>(p[0]) |
                            (static_cast<std::uint32_t>(p[1]) << 8) |
                            (static_cast<std::uint32_t>(p[2]) << 16);
    // Sign-extend bit 23.
    return (u & 0x800000U) ? static_cast<std::int32_t>(u) - 0x1000000
                           : static_cast<std::int32_t>(u);
}

void write_i24(std::uint8_t* p, std::int32_t v) {
    const auto u = static_cast<std::uint32_t>(v);
    p[0] = static_cast<std::uint8_t>(u);
    p[1] = static_cast<std::uint8_t>(u >> 8);
    p[2] = static_cast<std::uint8_t>(u >> 16);
}

std::int32_t quantise_i24(double value, double scale) {
    const double q = std::round(value / scale);
    if (!std::isfinite(q)) return kInvalidI24;
    if (q > kMaxI24) return kMaxI24;
    if (q < -kMaxI24) return -kMaxI24;
    return static_cast<std::int32_t>(q);
}

std::uint8_t checksum(std::span<const std::uint8_t, kPacketSize> p, int which) {
    const std::size_t end = kChecksumAt[which - 1];
    unsigned sum = 0;
    for (std::size_t i = 1; i < end; ++i) sum += p[i];
    return static_cast<std::uint8_t>(sum & 0xFFU);
}

bool checksums_ok(std::span<const std::uint8_t, kPacketSize> p) {
    // One running sum gives all three.
    unsigned sum = 0;
    std::size_t k = 0;
    for (std::size_t i = 1; i < kPacketSize && k < 3; ++i) {
        if (i == kChecksumAt[k]) {
            if (p[i] != static_cast<std::uint8_t>(sum & 0xFFU)) return false;
            ++k;
        }
        sum += p[i];
    }
    return true;
}

std::array<std::uint8_t, kPacketSize> pack(const Packet& p) {
    std::array<std::uint8_t, kPacketSize> b{};
    std::uint8_t* d = b.data();
    d[0] = kSync;
    d[1] = static_cast<std::uint8_t>(p.ms_of_minute);
    d[2] = static_cast<std::uint8_t>(p.ms_of_minute >> 8);
    for (std::size_t i = 0; i < 3; ++i) {
        write_i24(d + 3 + 3 * i, p.accel[i]);
        write_i24(d + 12 + 3 * i, p.rate[i]);
        write_i24(d + 43 + 3 * i, p.vel_ned[i]);
    }
    d[21] = p.nav_status;
    put_u64(d + 23, std::bit_cast<std::uint64_t>(p.lat_rad));
    put_u64(d + 31, std::bit_cast<std::uint64_t>(p.lon_rad));
    put_u32(d + 39, std::bit_cast<std::uint32_t>(p.alt_m));
    write_i24(d + 52, p.heading);
    write_i24(d + 55, p.pitch);
    write_i24(d + 58, p.roll);
    d[62] = p.channel;
    std::memcpy(d + 63, p.status.data(), p.status.size());
    for (int k = 1; k <= 3; ++k) b[kChecksumAt[k - 1]] = checksum(b, k);
    return b;
}

Packet unpack(std::span<const std::uint8_t, kPacketSize> b) {
    const std::uint8_t* d = b.data();
    Packet p;
    p.ms_of_minute = static_cast<std::uint16_t>(d[1] | (d[2] << 8));
    for (std::size_t i = 0; i < 3; ++i) {
        p.accel[i] = read_i24(d + 3 + 3 * i);
        p.rate[i] = read_i24(d + 12 + 3 * i);
        p.vel_ned[i] = read_i24(d + 43 + 3 * i);
    }
    p.nav_status = d[21];
    p.lat_rad = std::bit_cast<double>(get_u64(d + 23));
    p.lon_rad = std::bit_cast<double>(get_u64(d + 31));
    p.alt_m = std::bit_cast<float>(get_u32(d + 39));
    p.heading = read_i24(d + 52);
    p.pitch = read_i24(d + 55);
    p.roll = read_i24(d + 58);
    p.channel = d[62];
    std::memcpy(p.status.data(), d + 63, p.status.size());
    return p;
}

std::array<std::uint8_t, 8> pack_channel0(const Channel0& c) {
    std::array<std::uint8_t, 8> s{};
    put_u32(s.data(), static_cast<std::uint32_t>(c.gps_minutes));
    s[4] = c.satellites;
    s[5] = c.position_mode;
    s[6] = c.velocity_mode;
    s[7] = c.orientation_mode;
    return s;
}

Channel0 unpack_channel0(const std::array<std::uint8_t, 8>& s) {
    Channel0 c;
    c.gps_minutes = static_cast<std::int32_t>(get_u32(s.data()));
    c.satellites = s[4];
    c.position_mode = s[5];
    c.velocity_mode = s[6];
    c.orientation_mode = s[7];
    return c;
}

}  // namespace mirage::ncom
