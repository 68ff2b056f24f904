// SPDX-License-Identifier: Apache-2.0
#pragma once
// gs_usb host protocol, byte-exact (docs/nav-protocols.md §10.2): control-request payloads, bit
// timing and the bulk `gs_host_frame`. Pure functions, no libusb, so tests and fuzzers use them
// directly.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "mirage/nav/can_frame.hpp"

namespace mirage::can::gsusb {

// Control requests (bRequest).
inline constexpr std::uint8_t kReqHostFormat = 0;
inline constexpr std::uint8_t kReqBitTiming = 1;
inline constexpr std::uint8_t kReqMode = 2;
inline constexpr std::uint8_t kReqBtConst = 4;
inline constexpr std::uint8_t kReqDeviceConfig = 5;
// bmRequestType: vendor, interface recipient.
inline constexpr std::uint8_t kRequestTypeOut = 0x41;
inline constexpr std::uint8_t kRequestTypeIn = 0xC1;

inline constexpr std::uint32_t kHostFormat = 0x0000BEEF;
inline constexpr std::uint32_t kModeReset = 0;
inline constexpr std::uint32_t kModeStart = 1;
inline constexpr std::uint32_t kModeFlagListenOnly = 1u << 0;

// gs_host_frame.
inline constexpr std::uint32_t kEchoIdRx = 0xFFFFFFFF;  // frame received from the bus
inline constexpr std::uint32_t kCanEffFlag = 0x80000000;
inline constexpr std::uint32_t kCanRtrFlag = 0x40000000;
inline constexpr std::uint32_t kCanErrFlag = 0x20000000;
inline constexpr std::uint32_t kCanEffMask = 0x1FFFFFFF;
inline constexpr std::uint32_t kCanSffMask = 0x000007FF;
inline constexpr std::uint32_t kCanErrBusOff = 0x00000040;  // linux/can/error.h CAN_ERR_BUSOFF
inline constexpr std::uint8_t kFrameFlagFd = 1u << 1;
inline constexpr std::size_t kClassicFrameSize = 20;  // 24 with a HW timestamp
// Largest classic packet accepted: some firmwares pad to the 32-byte full-speed packet size.
inline constexpr std::size_t kClassicFrameMaxSize = 32;

inline void put_u32(std::uint8_t* p, std::uint32_t v) {
    p[0] = static_cast<std::uint8_t>(v);
    p[1] = static_cast<std::uint8_t>(v >> 8);
    p[2] = static_cast<std::uint8_t>(v >> 16);
    p[3] = static_cast<std::uint8_t>(v >> 24);
}
inline std::uint32_t get_u32(const std::uint8_t* p) {
    return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
           (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

// DEVICE_CONFIG reply (12 bytes).
struct DeviceConfig {
    std::uint8_t icount = 0;  // channels - 1
    std::uint32_t sw_version = 0;
    std::uint32_t hw_version = 0;
};
inline constexpr std::size_t kDeviceConfigSize = 12;
inline DeviceConfig parse_device_config(const std::uint8_t* p) {
    return DeviceConfig{p[3], get_u32(p + 4), get_u32(p + 8)};
}

// BT_CONST reply (40 bytes, ten LE u32).
struct BtConst {
    std::uint32_t feature = 0;
    std::uint32_t fclk_can = 0;
    std::uint32_t tseg1_min = 0, tseg1_max = 0;
    std::uint32_t tseg2_min = 0, tseg2_max = 0;
    std::uint32_t sjw_max = 0;
    std::uint32_t brp_min = 0, brp_max = 0, brp_inc = 0;
};
inline constexpr std::size_t kBtConstSize = 40;
inline BtConst parse_bt_const(const std::uint8_t* p) {
    BtConst c;
    c.feature = get_u32(p);
    c.fclk_can = get_u32(p + 4);
    c.tseg1_min = get_u32(p + 8);
    c.tseg1_max = get_u32(p + 12);
    c.tseg2_min = get_u32(p + 16);
    c.tseg2_max = get_u32(p + 20);
    c.sjw_max = get_u32(p + 24);
    c.brp_min = get_u32(p + 28);
    c.brp_max = get_u32(p + 32);
    c.brp_inc = get_u32(p + 36);
    return c;
}

// BITTIMING payload; bitrate = fclk / (brp * (1 + prop_seg + phase_seg1 + phase_seg2)).
struct BitTiming {
    std::uint32_t prop_seg = 0, phase_seg1 = 0, phase_seg2 = 0, sjw = 0, brp = 0;
    friend bool operator==(const BitTiming&, const BitTiming&) = default;
};
inline std::array<std::uint8_t, 20> encode_bit_timing(const BitTiming& bt) {
    std::array<std::uint8_t, 20> b{};
    put_u32(b.data(), bt.prop_seg);
    put_u32(b.data() + 4, bt.phase_seg1);
    put_u32(b.data() + 8, bt.phase_seg2);
    put_u32(b.data() + 12, bt.sjw);
    put_u32(b.data() + 16, bt.brp);
    return b;
}
inline std::uint32_t quanta_per_bit(const BitTiming& bt) {
    return 1 + bt.prop_seg + bt.phase_seg1 + bt.phase_seg2;
}
inline double sample_point(const BitTiming& bt) {
    return static_cast<double>(1 + bt.prop_seg + bt.phase_seg1) / quanta_per_bit(bt);
}

// Largest bitrate error accepted: CAN tolerates ~1.5 % total oscillator mismatch between nodes;
// keep our own share well under half of it.
inline constexpr double kMaxBitrateError = 0.005;

// Chooses the segments as Linux's can_calc_bittiming does: smallest bitrate error first, then
// the sample point closest to `sample_point_nominal`, preferring more time quanta per bit.
// Returns nothing when no brp/segment combination within the BT_CONST limits reaches the bitrate.
inline std::optional<BitTiming> compute_bit_timing(const BtConst& c, std::uint32_t bitrate,
                                                   double sample_point_nominal = 0.875) {
    if (bitrate == 0 || c.fclk_can == 0 || c.tseg1_max == 0 || c.tseg2_max == 0) return {};
    const std::uint64_t brp_inc = std::max<std::uint32_t>(1, c.brp_inc);
    const std::uint32_t tseg1_min = std::clamp<std::uint32_t>(c.tseg1_min, 1, 512);
    const std::uint32_t tseg2_min = std::clamp<std::uint32_t>(c.tseg2_min, 1, 512);
    // Bounds the search whatever the device claims (FDCAN, the widest, has 256 / 128).
    const std::uint32_t tseg1_max = std::min<std::uint32_t>(c.tseg1_max, 256);
    const std::uint32_t tseg2_max = std::min<std::uint32_t>(c.tseg2_max, 128);
    std::optional<BitTiming> best;
    std::uint64_t best_rate_err = UINT64_MAX;
    double best_sp_err = 1e9;
    for (std::uint32_t tseg = tseg1_max + tseg2_max; tseg >= tseg1_min + tseg2_min; --tseg) {
        const std::uint64_t quanta = tseg + 1;
        // Nearest brp, then down to a multiple of brp_inc.
        std::uint64_t brp = (c.fclk_can + bitrate * quanta / 2) / (bitrate * quanta);
        brp = (brp / brp_inc) * brp_inc;
        if (brp == 0 || brp < c.brp_min || brp > c.brp_max) continue;
        const std::uint64_t rate = c.fclk_can / (brp * quanta);
        const std::uint64_t rate_err = rate > bitrate ? rate - bitrate : bitrate - rate;
        if (rate_err > best_rate_err) continue;
        for (std::uint32_t tseg2 = tseg2_min; tseg2 <= tseg2_max && tseg2 < tseg; ++tseg2) {
            const std::uint32_t tseg1 = tseg - tseg2;
            if (tseg1 < tseg1_min || tseg1 > tseg1_max) continue;
            const double sp = static_cast<double>(1 + tseg1) / static_cast<double>(quanta);
            const double sp_err = std::abs(sp - sample_point_nominal);
            if (rate_err < best_rate_err || sp_err < best_sp_err - 1e-12) {
                BitTiming bt;
                bt.prop_seg = tseg1 / 2;  // split as Linux does; the controller adds them up
                bt.phase_seg1 = tseg1 - bt.prop_seg;
                bt.phase_seg2 = tseg2;
                bt.brp = static_cast<std::uint32_t>(brp);
                best = bt;
                best_rate_err = rate_err;
                best_sp_err = sp_err;
            }
        }
        if (best_rate_err == 0 && best_sp_err < 1e-12) break;
    }
    if (!best) return {};
    if (static_cast<double>(best_rate_err) > kMaxBitrateError * bitrate) return {};
    // Linux's default SJW: half of phase_seg2, at least 1, at most phase_seg1 and sjw_max.
    std::uint32_t sjw =
        std::max<std::uint32_t>(1, std::min(best->phase_seg1, best->phase_seg2 / 2));
    if (c.sjw_max > 0) sjw = std::min(sjw, c.sjw_max);
    best->sjw = sjw;
    return best;
}

// MODE payload (8 bytes).
inline std::array<std::uint8_t, 8> encode_mode(std::uint32_t mode, std::uint32_t flags) {
    std::array<std::uint8_t, 8> b{};
    put_u32(b.data(), mode);
    put_u32(b.data() + 4, flags);
    return b;
}

inline std::array<std::uint8_t, 4> encode_host_format() {
    std::array<std::uint8_t, 4> b{};
    put_u32(b.data(), kHostFormat);
    return b;
}

// A classic CAN frame as gs_host_frame (20 bytes, no timestamp). The caller checks the frame
// with `valid_tx_frame` first.
inline std::array<std::uint8_t, kClassicFrameSize> encode_host_frame(const nav::CanFrame& f,
                                                                     std::uint32_t echo_id,
                                                                     std::uint8_t channel) {
    std::array<std::uint8_t, kClassicFrameSize> b{};
    std::uint32_t can_id = f.extended ? (f.id & kCanEffMask) | kCanEffFlag : f.id & kCanSffMask;
    if (f.rtr) can_id |= kCanRtrFlag;
    put_u32(b.data(), echo_id);
    put_u32(b.data() + 4, can_id);
    b[8] = f.len;
    b[9] = channel;
    for (std::size_t i = 0; i < f.len && i < 8; ++i) b[12 + i] = f.data[i];
    return b;
}

inline bool valid_tx_frame(const nav::CanFrame& f) {
    if (f.error || f.len > 8) return false;
    return f.extended ? f.id <= kCanEffMask : f.id <= kCanSffMask;
}

enum class HostFrameKind : std::uint8_t {
    Received,   // a data or error frame from the bus
    Echo,       // the device confirms that our frame `echo_id` went out
    Malformed,  // not a valid classic gs_host_frame for this channel
};

struct DecodedHostFrame {
    HostFrameKind kind = HostFrameKind::Malformed;
    std::uint32_t echo_id = 0;
    nav::CanFrame frame;
};

// The one place where bytes from the device are validated: length, dlc <= 8, channel, no CAN FD,
// identifier within its range. Never reads outside [p, p + n).
inline DecodedHostFrame decode_host_frame(const std::uint8_t* p, std::size_t n,
                                          std::uint8_t channel) {
    DecodedHostFrame d;
    if (p == nullptr || n < kClassicFrameSize || n > kClassicFrameMaxSize) return d;
    const std::uint32_t echo_id = get_u32(p);
    const std::uint32_t can_id = get_u32(p + 4);
    const std::uint8_t dlc = p[8];
    if (dlc > 8 || p[9] != channel || (p[10] & kFrameFlagFd) != 0) return d;
    nav::CanFrame f;
    f.error = (can_id & kCanErrFlag) != 0;
    f.extended = !f.error && (can_id & kCanEffFlag) != 0;
    f.rtr = !f.error && (can_id & kCanRtrFlag) != 0;
    if (f.error) {
        f.id = can_id & kCanEffMask;  // CAN_ERR_* class bits
        if (echo_id != kEchoIdRx) return d;
    } else if (f.extended) {
        f.id = can_id & kCanEffMask;
    } else {
        if ((can_id & kCanEffMask) > kCanSffMask) return d;
        f.id = can_id & kCanSffMask;
    }
    f.len = dlc;
    for (std::size_t i = 0; i < dlc; ++i) f.data[i] = p[12 + i];
    d.frame = f;
    d.echo_id = echo_id;
    d.kind = echo_id == kEchoIdRx ? HostFrameKind::Received : HostFrameKind::Echo;
    return d;
}

}  // namespace mirage::can::gsusb
