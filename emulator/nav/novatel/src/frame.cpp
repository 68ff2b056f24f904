// SPDX-License-Identifier: Apache-2.0
#include "mirage/novatel/frame.hpp"

#include <algorithm>

#include "le_bytes.hpp"
#include "mirage/novatel/crc32.hpp"

namespace mirage::novatel {
using namespace detail;

namespace {
// `out` is sized header + body + CRC up front (growing it by insert trips GCC 12's
// -Warray-bounds false positive); copies the body in and appends the CRC.
void finish_frame(std::vector<std::uint8_t>& out, std::size_t hlen,
                  std::span<const std::uint8_t> body) {
    std::copy(body.begin(), body.end(), out.begin() + static_cast<std::ptrdiff_t>(hlen));
    const std::size_t n = hlen + body.size();
    put_u32(out.data() + n, crc32(std::span<const std::uint8_t>(out.data(), n)));
}
}  // namespace

std::vector<std::uint8_t> frame_long(LongHeader h, std::span<const std::uint8_t> body) {
    h.body_length = static_cast<std::uint16_t>(body.size());
    // A header longer than 28 bytes (allowed by the length byte) is padded with zeros.
    const std::size_t hlen = h.header_length < kLongHeaderSize ? kLongHeaderSize : h.header_length;
    std::vector<std::uint8_t> out(hlen + body.size() + kCrcSize, 0);
    std::uint8_t* p = out.data();
    p[0] = kSync0;
    p[1] = kSync1;
    p[2] = kSyncLong;
    p[3] = static_cast<std::uint8_t>(hlen);
    put_u16(p + 4, h.message_id);
    p[6] = h.message_type;
    p[7] = h.port_address;
    put_u16(p + 8, h.body_length);
    put_u16(p + 10, h.sequence);
    p[12] = h.idle_time;
    p[13] = h.time_status;
    put_u16(p + 14, h.week);
    put_u32(p + 16, h.ms_of_week);
    put_u32(p + 20, h.receiver_status);
    put_u16(p + 24, h.reserved);
    put_u16(p + 26, h.software_build);
    finish_frame(out, hlen, body);
    return out;
}

std::vector<std::uint8_t> frame_short(ShortHeader h, std::span<const std::uint8_t> body) {
    h.body_length = static_cast<std::uint8_t>(body.size());
    std::vector<std::uint8_t> out(kShortHeaderSize + body.size() + kCrcSize, 0);
    std::uint8_t* p = out.data();
    p[0] = kSync0;
    p[1] = kSync1;
    p[2] = kSyncShort;
    p[3] = h.body_length;
    put_u16(p + 4, h.message_id);
    put_u16(p + 6, h.week);
    put_u32(p + 8, h.ms_of_week);
    finish_frame(out, kShortHeaderSize, body);
    return out;
}

std::optional<LongHeader> parse_long_header(std::span<const std::uint8_t> f) {
    if (f.size() < kLongHeaderSize || f[0] != kSync0 || f[1] != kSync1 || f[2] != kSyncLong ||
        f[3] < kLongHeaderSize || f.size() < f[3])
        return std::nullopt;
    const std::uint8_t* p = f.data();
    LongHeader h;
    h.header_length = p[3];
    h.message_id = get_u16(p + 4);
    h.message_type = p[6];
    h.port_address = p[7];
    h.body_length = get_u16(p + 8);
    h.sequence = get_u16(p + 10);
    h.idle_time = p[12];
    h.time_status = p[13];
    h.week = get_u16(p + 14);
    h.ms_of_week = get_u32(p + 16);
    h.receiver_status = get_u32(p + 20);
    h.reserved = get_u16(p + 24);
    h.software_build = get_u16(p + 26);
    return h;
}

std::optional<ShortHeader> parse_short_header(std::span<const std::uint8_t> f) {
    if (f.size() < kShortHeaderSize || f[0] != kSync0 || f[1] != kSync1 || f[2] != kSyncShort)
        return std::nullopt;
    const std::uint8_t* p = f.data();
    ShortHeader h;
    h.body_length = p[3];
    h.message_id = get_u16(p + 4);
    h.week = get_u16(p + 6);
    h.ms_of_week = get_u32(p + 8);
    return h;
}

}  // namespace mirage::novatel
