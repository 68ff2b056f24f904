// SPDX-License-Identifier: Apache-2.0
// gs_usb bytes and bit timing without libusb (docs/nav-protocols.md §10.2).
#include "gsusb_protocol.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace {

using namespace mirage::can::gsusb;
using mirage::nav::CanFrame;

BtConst bxcan_48mhz() {
    BtConst c;
    c.fclk_can = 48'000'000;
    c.tseg1_min = 1;
    c.tseg1_max = 16;
    c.tseg2_min = 1;
    c.tseg2_max = 8;
    c.sjw_max = 4;
    c.brp_min = 1;
    c.brp_max = 1024;
    c.brp_inc = 1;
    return c;
}

TEST(GsUsbBitTiming, candlelight_500k_is_brp6_prop6_ps1_7_ps2_2_sjw1) {
    const auto bt = compute_bit_timing(bxcan_48mhz(), 500'000);
    ASSERT_TRUE(bt.has_value());
    EXPECT_EQ(*bt, (BitTiming{6, 7, 2, 1, 6}));
    EXPECT_EQ(48'000'000u / (bt->brp * quanta_per_bit(*bt)), 500'000u);
    EXPECT_DOUBLE_EQ(sample_point(*bt), 0.875);
}

TEST(GsUsbBitTiming, common_bitrates_are_exact_at_87_5_percent_for_several_clocks) {
    for (std::uint32_t fclk : {48'000'000u, 80'000'000u, 16'000'000u, 24'000'000u}) {
        for (std::uint32_t rate : {1'000'000u, 500'000u, 250'000u, 125'000u, 100'000u}) {
            BtConst c = bxcan_48mhz();
            c.fclk_can = fclk;
            const auto bt = compute_bit_timing(c, rate);
            ASSERT_TRUE(bt.has_value()) << fclk << " " << rate;
            const std::uint32_t tq = quanta_per_bit(*bt);
            EXPECT_EQ(fclk % (bt->brp * tq), 0u) << fclk << " " << rate;
            EXPECT_EQ(fclk / (bt->brp * tq), rate) << fclk << " " << rate;
            EXPECT_NEAR(sample_point(*bt), 0.875, 0.0626) << fclk << " " << rate;
            EXPECT_LE(bt->prop_seg + bt->phase_seg1, 16u);
            EXPECT_LE(bt->phase_seg2, 8u);
            EXPECT_GE(bt->sjw, 1u);
            EXPECT_LE(bt->sjw, 4u);
        }
    }
    // 80 MHz, 500 kbit/s: 160 tq per bit → brp 10 × 16 tq, sample point exactly 87.5 %.
    BtConst c = bxcan_48mhz();
    c.fclk_can = 80'000'000;
    EXPECT_EQ(*compute_bit_timing(c, 500'000), (BitTiming{6, 7, 2, 1, 10}));
}

TEST(GsUsbBitTiming, brp_increment_is_respected) {
    BtConst c = bxcan_48mhz();
    c.brp_inc = 4;  // brp 6 not allowed → 4 or 8
    const auto bt = compute_bit_timing(c, 500'000);
    ASSERT_TRUE(bt.has_value());
    EXPECT_EQ(bt->brp % 4, 0u);
    EXPECT_EQ(48'000'000u / (bt->brp * quanta_per_bit(*bt)), 500'000u);
}

TEST(GsUsbBitTiming, unreachable_bitrates_give_nothing) {
    EXPECT_FALSE(compute_bit_timing(bxcan_48mhz(), 1000).has_value());       // < 1875 bit/s
    EXPECT_FALSE(compute_bit_timing(bxcan_48mhz(), 7'000'000).has_value());  // 2 % off at best
    EXPECT_FALSE(compute_bit_timing(bxcan_48mhz(), 0).has_value());
    BtConst none;
    EXPECT_FALSE(compute_bit_timing(none, 500'000).has_value());
}

TEST(GsUsbBytes, control_payloads_are_little_endian) {
    EXPECT_EQ(encode_host_format(), (std::array<std::uint8_t, 4>{0xEF, 0xBE, 0, 0}));
    EXPECT_EQ(encode_mode(kModeStart, kModeFlagListenOnly),
              (std::array<std::uint8_t, 8>{1, 0, 0, 0, 1, 0, 0, 0}));
    const auto bt = encode_bit_timing(BitTiming{6, 7, 2, 1, 0x0102});
    EXPECT_EQ(bt[0], 6);
    EXPECT_EQ(bt[4], 7);
    EXPECT_EQ(bt[8], 2);
    EXPECT_EQ(bt[12], 1);
    EXPECT_EQ(bt[16], 0x02);
    EXPECT_EQ(bt[17], 0x01);
    std::array<std::uint8_t, 40> raw{};
    for (std::size_t i = 0; i < 10; ++i)
        put_u32(raw.data() + 4 * i, static_cast<std::uint32_t>(i + 1));
    const BtConst c = parse_bt_const(raw.data());
    EXPECT_EQ(c.feature, 1u);
    EXPECT_EQ(c.fclk_can, 2u);
    EXPECT_EQ(c.brp_inc, 10u);
    const std::array<std::uint8_t, 12> dc{0, 0, 0, 2, 5, 0, 0, 0, 7, 0, 0, 0};
    const DeviceConfig d = parse_device_config(dc.data());
    EXPECT_EQ(d.icount, 2);
    EXPECT_EQ(d.sw_version, 5u);
    EXPECT_EQ(d.hw_version, 7u);
}

TEST(GsUsbBytes, tx_frame_0x601_is_byte_exact) {
    CanFrame f;
    f.id = 0x601;
    f.len = 8;
    f.data = {0x08, 0x1E, 0xAE, 0x1C, 0x18, 0x4F, 0xDD, 0x06};
    const auto b = encode_host_frame(f, 3, 0);
    const std::array<std::uint8_t, 20> want{3, 0, 0,    0,    0x01, 0x06, 0,    0,    8,    0,
                                            0, 0, 0x08, 0x1E, 0xAE, 0x1C, 0x18, 0x4F, 0xDD, 0x06};
    EXPECT_EQ(b, want);
    CanFrame x;
    x.id = 0x18FF1234;
    x.extended = true;
    x.rtr = true;
    x.len = 0;
    const auto bx = encode_host_frame(x, 0, 1);
    EXPECT_EQ(get_u32(bx.data() + 4), 0x18FF1234u | kCanEffFlag | kCanRtrFlag);
    EXPECT_EQ(bx[9], 1);
}

TEST(GsUsbBytes, rx_frame_0x607_decodes_and_round_trips) {
    CanFrame f;
    f.id = 0x607;
    f.len = 6;
    f.data = {0xF8, 0x20, 0x78, 0x00, 0xCE, 0xFF, 0, 0};
    auto b = encode_host_frame(f, kEchoIdRx, 0);
    b[18] = 0xEE;  // bytes past dlc are not part of the frame
    const DecodedHostFrame d = decode_host_frame(b.data(), b.size(), 0);
    EXPECT_EQ(d.kind, HostFrameKind::Received);
    EXPECT_EQ(d.frame, f);
    // With a 4-byte hardware timestamp (24 bytes) too.
    std::vector<std::uint8_t> ts(b.begin(), b.end());
    ts.insert(ts.end(), {1, 2, 3, 4});
    EXPECT_EQ(decode_host_frame(ts.data(), ts.size(), 0).frame, f);
    // Echo.
    const auto e = encode_host_frame(f, 5, 0);
    const DecodedHostFrame de = decode_host_frame(e.data(), e.size(), 0);
    EXPECT_EQ(de.kind, HostFrameKind::Echo);
    EXPECT_EQ(de.echo_id, 5u);
}

TEST(GsUsbBytes, error_frame_keeps_class_bits) {
    std::array<std::uint8_t, 20> b{};
    put_u32(b.data(), kEchoIdRx);
    put_u32(b.data() + 4, kCanErrFlag | kCanErrBusOff);
    b[8] = 8;
    const DecodedHostFrame d = decode_host_frame(b.data(), b.size(), 0);
    EXPECT_EQ(d.kind, HostFrameKind::Received);
    EXPECT_TRUE(d.frame.error);
    EXPECT_FALSE(d.frame.extended);
    EXPECT_EQ(d.frame.id, kCanErrBusOff);
}

TEST(GsUsbBytes, malformed_packets_are_rejected) {
    CanFrame f;
    f.id = 0x100;
    f.len = 1;
    const auto good = encode_host_frame(f, kEchoIdRx, 0);
    auto bad = [&](auto edit, std::size_t n = 20, std::uint8_t channel = 0) {
        std::array<std::uint8_t, 40> b{};
        std::copy(good.begin(), good.end(), b.begin());
        edit(b);
        return decode_host_frame(b.data(), n, channel).kind == HostFrameKind::Malformed;
    };
    EXPECT_TRUE(bad([](auto&) {}, 19));                       // short
    EXPECT_TRUE(bad([](auto&) {}, 33));                       // longer than any classic frame
    EXPECT_TRUE(bad([](auto& b) { b[8] = 9; }));              // dlc > 8
    EXPECT_TRUE(bad([](auto&) {}, 20, 1));                    // other channel
    EXPECT_TRUE(bad([](auto& b) { b[10] = kFrameFlagFd; }));  // CAN FD not enabled
    EXPECT_TRUE(bad([](auto& b) { b[5] = 0x08; }));           // standard id 0x800
    EXPECT_TRUE(bad([](auto& b) {                             // error frame as an echo
        put_u32(b.data(), 0);
        put_u32(b.data() + 4, kCanErrFlag);
    }));
    EXPECT_FALSE(bad([](auto&) {}));
    EXPECT_EQ(decode_host_frame(nullptr, 20, 0).kind, HostFrameKind::Malformed);
}

TEST(GsUsbBytes, random_bytes_never_yield_an_out_of_range_frame) {
    std::mt19937 rng(42);
    std::vector<std::uint8_t> buf(40);
    int accepted = 0;
    for (int i = 0; i < 20000; ++i) {
        for (auto& x : buf) x = static_cast<std::uint8_t>(rng());
        buf[8] = static_cast<std::uint8_t>(rng() % 12);
        buf[9] = static_cast<std::uint8_t>(rng() % 2);
        const std::size_t n = 16 + rng() % 20;
        const DecodedHostFrame d = decode_host_frame(buf.data(), n, 0);
        if (d.kind == HostFrameKind::Malformed) continue;
        ++accepted;
        EXPECT_LE(d.frame.len, 8);
        EXPECT_LE(d.frame.id, kCanEffMask);
        if (!d.frame.extended && !d.frame.error) {
            EXPECT_LE(d.frame.id, kCanSffMask);
        }
        for (std::size_t k = d.frame.len; k < 8; ++k) EXPECT_EQ(d.frame.data[k], 0);
    }
    EXPECT_GT(accepted, 100);
}

}  // namespace
