// SPDX-License-Identifier: Apache-2.0
// GsUsbBus against a fake candleLight under umockdev (docs/nav-protocols.md §10.2, §13.3). Runs
// under `umockdev-wrapper` (LD_PRELOAD); skips with a message otherwise.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "fake_candlelight.hpp"
#include "mirage/can/gsusb_bus.hpp"
#include "mirage/core/error.hpp"
#include "test_paths.hpp"

namespace {

using mirage::can::BusCounters;
using mirage::can::CanBus;
using mirage::can::GsUsbOptions;
using mirage::can::RxStatus;
using mirage::nav::CanFrame;
using mirage::test::FakeCandleLight;
using namespace std::chrono_literals;

constexpr const char* kDevNode = "/dev/bus/usb/001/002";

std::vector<std::uint8_t> u32s(std::initializer_list<std::uint32_t> values) {
    std::vector<std::uint8_t> v;
    for (std::uint32_t x : values)
        for (int i = 0; i < 4; ++i) v.push_back(static_cast<std::uint8_t>(x >> (8 * i)));
    return v;
}

// gs_host_frame as the device sends it (20 bytes).
std::vector<std::uint8_t> host_frame(std::uint32_t echo_id, std::uint32_t can_id, std::uint8_t dlc,
                                     std::vector<std::uint8_t> data, std::uint8_t channel = 0) {
    std::vector<std::uint8_t> p = u32s({echo_id, can_id});
    p.push_back(dlc);
    p.push_back(channel);
    p.push_back(0);
    p.push_back(0);
    data.resize(8, 0);
    p.insert(p.end(), data.begin(), data.end());
    return p;
}

CanFrame frame(std::uint32_t id, std::vector<std::uint8_t> data, bool extended = false) {
    CanFrame f;
    f.id = id;
    f.extended = extended;
    f.len = static_cast<std::uint8_t>(data.size());
    for (std::size_t i = 0; i < data.size(); ++i) f.data[i] = data[i];
    return f;
}

class GsUsbUmockdev : public ::testing::Test {
  protected:
    void SetUp() override {
        const char* preload = std::getenv("LD_PRELOAD");
        if (preload == nullptr || std::strstr(preload, "libumockdev-preload") == nullptr)
            GTEST_SKIP() << "not under umockdev-wrapper (LD_PRELOAD of libumockdev-preload); "
                            "run via ctest or `umockdev-wrapper <test>`";
        testbed_ = umockdev_testbed_new();
        const auto desc = mirage::test::source_dir() / "tests/drivers/can/candlelight.umockdev";
        GError* error = nullptr;
        ASSERT_TRUE(umockdev_testbed_add_from_file(testbed_, desc.c_str(), &error))
            << (error ? error->message : "?");
        fake_ = std::make_unique<FakeCandleLight>();
        ASSERT_TRUE(umockdev_testbed_attach_ioctl(testbed_, kDevNode, fake_->handler(), &error))
            << (error ? error->message : "?");
    }
    void TearDown() override {
        if (testbed_ != nullptr) {
            if (fake_) {
                EXPECT_TRUE(fake_->unknown_requests().empty())
                    << "unhandled usbdevfs ioctl 0x" << std::hex
                    << fake_->unknown_requests().front();
            }
            umockdev_testbed_detach_ioctl(testbed_, kDevNode, nullptr);
            g_object_unref(testbed_);
        }
        fake_.reset();
    }

    // Reads until a frame or error frame arrives (bounded), skipping timeouts.
    static RxStatus next(CanBus& bus, CanFrame& out, std::int64_t& host_ns) {
        for (int i = 0; i < 100; ++i) {
            const RxStatus s = bus.receive(out, host_ns, 20ms);
            if (s != RxStatus::Timeout) return s;
        }
        return RxStatus::Timeout;
    }

    // Lets the bus's event thread run until `pred(counters)` holds (bounded, no sleep).
    template <class Pred>
    static BusCounters wait_counters(CanBus& bus, Pred pred) {
        CanFrame f;
        std::int64_t t = 0;
        for (int i = 0; i < 200 && !pred(bus.counters()); ++i) bus.receive(f, t, 10ms);
        return bus.counters();
    }

    UMockdevTestbed* testbed_ = nullptr;
    std::unique_ptr<FakeCandleLight> fake_;
};

TEST_F(GsUsbUmockdev, start_up_sends_the_linux_sequence_with_500k_bit_timing) {
    auto bus = mirage::can::open_gsusb(GsUsbOptions{});
    EXPECT_EQ(bus->name(), "gsusb:1d50:606f");
    const auto c = fake_->controls();
    ASSERT_EQ(c.size(), 5u);
    // HOST_FORMAT: 0x41, bRequest 0, wValue 1, wIndex 0, 0x0000BEEF.
    EXPECT_EQ(c[0].request_type, 0x41);
    EXPECT_EQ(c[0].request, 0);
    EXPECT_EQ(c[0].value, 1);
    EXPECT_EQ(c[0].index, 0);
    EXPECT_EQ(c[0].data, (std::vector<std::uint8_t>{0xEF, 0xBE, 0x00, 0x00}));
    // DEVICE_CONFIG then BT_CONST, device → host.
    EXPECT_EQ(c[1].request_type, 0xC1);
    EXPECT_EQ(c[1].request, 5);
    EXPECT_EQ(c[1].value, 1);
    EXPECT_EQ(c[1].data.size(), 12u);
    EXPECT_EQ(c[2].request_type, 0xC1);
    EXPECT_EQ(c[2].request, 4);
    EXPECT_EQ(c[2].value, 0);
    EXPECT_EQ(c[2].data.size(), 40u);
    // BITTIMING for 500 kbit/s from fclk 48 MHz, tseg1 1..16, tseg2 1..8, sjw_max 4:
    // brp 6, 1 + 6 + 7 + 2 = 16 tq → 48e6 / (6·16) = 500000, sample point 14/16 = 87.5 %.
    EXPECT_EQ(c[3].request_type, 0x41);
    EXPECT_EQ(c[3].request, 1);
    EXPECT_EQ(c[3].value, 0);
    EXPECT_EQ(c[3].data, u32s({6, 7, 2, 1, 6}));
    const std::uint32_t brp = 6, tq = 1 + 6 + 7 + 2;
    EXPECT_EQ(FakeCandleLight::kFclk / (brp * tq), 500'000u);
    // MODE START, no flags.
    EXPECT_EQ(c[4].request_type, 0x41);
    EXPECT_EQ(c[4].request, 2);
    EXPECT_EQ(c[4].data, u32s({1, 0}));
    // Eight bulk-IN transfers stay queued.
    EXPECT_TRUE(fake_->wait_until([&] { return fake_->pending_in() == 8; }));
}

TEST_F(GsUsbUmockdev, listen_only_sets_mode_flag_and_close_resets) {
    GsUsbOptions o;
    o.listen_only = true;
    o.bitrate = 250'000;
    {
        auto bus = mirage::can::open_gsusb(o);
        const auto c = fake_->controls();
        ASSERT_EQ(c.size(), 5u);
        EXPECT_EQ(c[3].data, u32s({6, 7, 2, 1, 12}));  // 48e6 / (12·16) = 250000
        EXPECT_EQ(c[4].data, u32s({1, 1}));            // START, listen-only
    }
    const auto c = fake_->controls();
    ASSERT_EQ(c.size(), 6u);
    EXPECT_EQ(c[5].request, 2);
    EXPECT_EQ(c[5].data, u32s({0, 0}));  // MODE RESET on close
}

TEST_F(GsUsbUmockdev, tx_frame_goes_out_byte_exact_and_its_echo_is_counted) {
    auto bus = mirage::can::open_gsusb(GsUsbOptions{});
    // OxTS 0x601 LatitudeLongitude from docs/nav-protocols.md §7.1: 081EAE1C184FDD06.
    ASSERT_TRUE(bus->send(frame(0x601, {0x08, 0x1E, 0xAE, 0x1C, 0x18, 0x4F, 0xDD, 0x06})));
    const BusCounters k =
        wait_counters(*bus, [](const BusCounters& c) { return c.tx_frames == 1; });
    EXPECT_EQ(k.tx_frames, 1u);
    EXPECT_EQ(k.tx_failed, 0u);
    EXPECT_EQ(k.malformed, 0u);
    EXPECT_EQ(k.rx_frames, 0u);  // the echo is a confirmation, not a received frame
    const auto out = fake_->bulk_out();
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0], host_frame(0, 0x601, 8, {0x08, 0x1E, 0xAE, 0x1C, 0x18, 0x4F, 0xDD, 0x06}));
    // Extended id and a second echo id from the pool.
    ASSERT_TRUE(bus->send(frame(0x18FF1234, {0xAA}, true)));
    wait_counters(*bus, [](const BusCounters& c) { return c.tx_frames == 2; });
    const auto out2 = fake_->bulk_out();
    ASSERT_EQ(out2.size(), 2u);
    EXPECT_EQ(out2[1][4], 0x34);
    EXPECT_EQ(out2[1][7], 0x98);  // 0x18 | EFF flag 0x80
    EXPECT_EQ(bus->counters().tx_frames, 2u);
}

TEST_F(GsUsbUmockdev, rx_frame_from_the_device_arrives_equal) {
    auto bus = mirage::can::open_gsusb(GsUsbOptions{});
    // OxTS 0x607 HeadingPitchRoll: F8207800CEFF (84.40°, 1.20°, −0.50°).
    fake_->inject(host_frame(0xFFFFFFFF, 0x607, 6, {0xF8, 0x20, 0x78, 0x00, 0xCE, 0xFF}));
    CanFrame f;
    std::int64_t host_ns = 0;
    ASSERT_EQ(next(*bus, f, host_ns), RxStatus::Frame);
    EXPECT_EQ(f, frame(0x607, {0xF8, 0x20, 0x78, 0x00, 0xCE, 0xFF}));
    EXPECT_GT(host_ns, 0);
    fake_->inject(host_frame(0xFFFFFFFF, 0x80000000u | 0x18FF1234u, 2, {1, 2}));
    ASSERT_EQ(next(*bus, f, host_ns), RxStatus::Frame);
    EXPECT_EQ(f, frame(0x18FF1234, {1, 2}, true));
    EXPECT_EQ(bus->counters().rx_frames, 2u);
}

TEST_F(GsUsbUmockdev, burst_of_200_frames_arrives_complete_and_in_order) {
    auto bus = mirage::can::open_gsusb(GsUsbOptions{});
    constexpr int kCount = 200;  // 25× the eight queued IN transfers: each is resubmitted
    for (int i = 0; i < kCount; ++i)
        fake_->inject(
            host_frame(0xFFFFFFFF, 0x600, 2,
                       {static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(i >> 8)}));
    CanFrame f;
    std::int64_t host_ns = 0, last_ns = 0;
    for (int i = 0; i < kCount; ++i) {
        ASSERT_EQ(next(*bus, f, host_ns), RxStatus::Frame) << i;
        ASSERT_EQ(f.data[0] | (f.data[1] << 8), i);
        EXPECT_GE(host_ns, last_ns);
        last_ns = host_ns;
    }
    EXPECT_EQ(bus->counters().rx_frames, static_cast<std::uint64_t>(kCount));
}

TEST_F(GsUsbUmockdev, error_frame_with_bus_off_is_reported_and_counted) {
    auto bus = mirage::can::open_gsusb(GsUsbOptions{});
    fake_->inject(host_frame(0xFFFFFFFF, 0x20000000u | 0x40u, 8, {0, 0, 0, 0, 0, 0, 0, 0}));
    CanFrame f;
    std::int64_t host_ns = 0;
    ASSERT_EQ(next(*bus, f, host_ns), RxStatus::ErrorFrame);
    EXPECT_TRUE(f.error);
    EXPECT_EQ(f.id, 0x40u);
    const BusCounters k = bus->counters();
    EXPECT_EQ(k.error_frames, 1u);
    EXPECT_EQ(k.bus_off, 1u);
    EXPECT_EQ(k.rx_frames, 0u);
}

TEST_F(GsUsbUmockdev, malformed_packets_are_counted_and_the_stream_goes_on) {
    auto bus = mirage::can::open_gsusb(GsUsbOptions{});
    fake_->inject(host_frame(0xFFFFFFFF, 0x123, 9, {}));      // dlc 9
    fake_->inject(host_frame(0xFFFFFFFF, 0x123, 1, {1}, 3));  // channel 3
    fake_->inject(std::vector<std::uint8_t>(12, 0));          // short
    fake_->inject(host_frame(7, 0x123, 1, {1}));              // echo of nothing we sent
    fake_->inject(host_frame(0xFFFFFFFF, 0x123, 1, {0x5A}));  // good
    CanFrame f;
    std::int64_t host_ns = 0;
    ASSERT_EQ(next(*bus, f, host_ns), RxStatus::Frame);
    EXPECT_EQ(f, frame(0x123, {0x5A}));
    const BusCounters k = bus->counters();
    EXPECT_EQ(k.malformed, 4u);
    EXPECT_EQ(k.rx_frames, 1u);
}

TEST_F(GsUsbUmockdev, bulk_in_timeout_is_clean_and_close_discards_queued_transfers) {
    {
        auto bus = mirage::can::open_gsusb(GsUsbOptions{});
        CanFrame f;
        std::int64_t host_ns = 0;
        EXPECT_EQ(bus->receive(f, host_ns, 30ms), RxStatus::Timeout);
        const BusCounters k = bus->counters();
        EXPECT_EQ(k.rx_frames + k.error_frames + k.malformed + k.tx_failed, 0u);
        fake_->inject(host_frame(0xFFFFFFFF, 0x602, 4, {0x78, 0x52, 0x08, 0x00}));
        ASSERT_EQ(next(*bus, f, host_ns), RxStatus::Frame);
        EXPECT_EQ(f, frame(0x602, {0x78, 0x52, 0x08, 0x00}));
    }
    // Closing cancelled all eight IN URBs via DISCARDURB and reaped them (no hang).
    EXPECT_EQ(fake_->discards(), 8);
    EXPECT_EQ(fake_->pending_in(), 0u);
}

TEST_F(GsUsbUmockdev, unplug_gives_closed_and_send_fails) {
    auto bus = mirage::can::open_gsusb(GsUsbOptions{});
    ASSERT_TRUE(fake_->wait_until([&] { return fake_->pending_in() == 8; }));
    fake_->unplug();
    CanFrame f;
    std::int64_t host_ns = 0;
    EXPECT_EQ(next(*bus, f, host_ns), RxStatus::Closed);
    EXPECT_FALSE(bus->send(frame(0x601, {1})));
    EXPECT_EQ(bus->counters().tx_failed, 1u);
}

TEST_F(GsUsbUmockdev, tx_pool_exhausts_without_echoes) {
    fake_->set_echo(false);
    auto bus = mirage::can::open_gsusb(GsUsbOptions{});
    for (int i = 0; i < 10; ++i)
        EXPECT_TRUE(bus->send(frame(0x100, {static_cast<std::uint8_t>(i)})));
    EXPECT_FALSE(bus->send(frame(0x100, {0xFF})));
    const BusCounters k = bus->counters();
    EXPECT_EQ(k.tx_frames, 0u);
    EXPECT_EQ(k.tx_failed, 1u);
    // Echo ids 0..9 went out in order.
    EXPECT_TRUE(fake_->wait_until([&] { return fake_->bulk_out().size() == 10; }));
    const auto out = fake_->bulk_out();
    for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i][0], i);
}

TEST_F(GsUsbUmockdev, serial_selects_the_device) {
    GsUsbOptions o;
    o.serial = FakeCandleLight::kSerial;
    EXPECT_NO_THROW(mirage::can::open_gsusb(o));
    o.serial = "OTHER";
    try {
        mirage::can::open_gsusb(o);
        FAIL() << "expected IoError";
    } catch (const mirage::IoError& e) {
        EXPECT_STREQ(e.what(), "gsusb 1d50:606f: no such device with serial 'OTHER'");
    }
}

TEST_F(GsUsbUmockdev, other_vid_pid_is_no_such_device) {
    GsUsbOptions o;
    o.vendor_id = 0x1209;
    o.product_id = 0x2323;
    try {
        mirage::can::open_gsusb(o);
        FAIL() << "expected IoError";
    } catch (const mirage::IoError& e) {
        EXPECT_STREQ(e.what(), "gsusb 1209:2323: no such device");
    }
    EXPECT_TRUE(fake_->controls().empty());
}

TEST_F(GsUsbUmockdev, unreachable_bitrate_is_a_config_error_before_bittiming) {
    GsUsbOptions o;
    o.bitrate = 1000;  // below 48e6 / (1024 · 25) = 1875 bit/s
    try {
        mirage::can::open_gsusb(o);
        FAIL() << "expected ConfigError";
    } catch (const mirage::ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("gsusb 1d50:606f: bitrate 1000 not reachable"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_EQ(fake_->controls().size(), 3u);  // HOST_FORMAT, DEVICE_CONFIG, BT_CONST only
}

}  // namespace
