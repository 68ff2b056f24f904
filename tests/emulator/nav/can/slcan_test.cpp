// SPDX-License-Identifier: Apache-2.0
#include "mirage/navcan/slcan.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

using namespace mirage;
using navcan::SlcanCommand;
using navcan::SlcanEvent;

namespace {

nav::CanFrame frame(std::uint32_t id, bool ext, std::vector<std::uint8_t> bytes, bool rtr = false) {
    nav::CanFrame f;
    f.id = id;
    f.extended = ext;
    f.rtr = rtr;
    f.len = static_cast<std::uint8_t>(bytes.size());
    for (std::size_t i = 0; i < bytes.size(); ++i) f.data[i] = bytes[i];
    return f;
}

std::vector<SlcanEvent> parse_all(navcan::SlcanParser& p, const std::string& text) {
    std::vector<SlcanEvent> ev;
    p.feed(text, [&](const SlcanEvent& e) { ev.push_back(e); });
    return ev;
}

}  // namespace

TEST(Slcan, encodes_the_lines_observed_with_linux_slcand) {
    // §9: `cansend can0 123#DEADBEEF` appears on the line as `t1234DEADBEEF\r`.
    EXPECT_EQ(navcan::slcan_encode(frame(0x123, false, {0xDE, 0xAD, 0xBE, 0xEF})),
              "t1234DEADBEEF\r");
    EXPECT_EQ(navcan::slcan_encode(frame(0x607, false, {0xF8, 0x20, 0x78, 0x00, 0xCE, 0xFF})),
              "t6076F8207800CEFF\r");
    EXPECT_EQ(navcan::slcan_encode(
                  frame(0x18FF50E5, true, {0xAA, 0xBB, 0xCC, 0xDD, 0x11, 0x22, 0x33, 0x44})),
              "T18FF50E58AABBCCDD11223344\r");
    EXPECT_EQ(navcan::slcan_encode(frame(0x123, false, {0, 0}, true)), "r1232\r");
    EXPECT_EQ(navcan::slcan_encode(frame(0x1ABCDEF0, true, {}, true)), "R1ABCDEF00\r");
    EXPECT_EQ(navcan::slcan_encode(frame(0x7FF, false, {}), 0xEA5F), "t7FF0EA5F\r");
    nav::CanFrame err = frame(0x4, false, {0, 0, 0, 0, 0, 0, 0, 0});
    err.error = true;
    EXPECT_EQ(navcan::slcan_encode(err), "");
}

TEST(Slcan, parses_frames_with_and_without_z_timestamps) {
    navcan::SlcanParser p;
    auto ev = parse_all(p, "t6076F8207800CEFF\rT18FF50E58AABBCCDD11223344\rt1230ABCD\rr1232\r");
    ASSERT_EQ(ev.size(), 4u);
    EXPECT_EQ(ev[0].frame, frame(0x607, false, {0xF8, 0x20, 0x78, 0x00, 0xCE, 0xFF}));
    EXPECT_FALSE(ev[0].timestamp_ms.has_value());
    EXPECT_EQ(ev[1].frame,
              frame(0x18FF50E5, true, {0xAA, 0xBB, 0xCC, 0xDD, 0x11, 0x22, 0x33, 0x44}));
    EXPECT_EQ(ev[2].frame, frame(0x123, false, {}));
    ASSERT_TRUE(ev[2].timestamp_ms.has_value());
    EXPECT_EQ(*ev[2].timestamp_ms, 0xABCD);
    EXPECT_TRUE(ev[3].frame.rtr);
    EXPECT_EQ(ev[3].frame.len, 2);
    EXPECT_EQ(p.counters().frames, 4u);
    EXPECT_EQ(p.counters().malformed, 0u);
}

TEST(Slcan, parses_commands_and_replies) {
    navcan::SlcanParser p;
    // What slcand sends on attach, then replies an adapter gives.
    auto ev = parse_all(p, "C\rS6\rO\rs031C\rL\rF\rF00\rV\rV1013\rN\rNA1B2\rZ1\rz\r\r\a");
    ASSERT_EQ(ev.size(), 15u);
    using K = SlcanCommand::Kind;
    EXPECT_EQ(ev[0].command.kind, K::Close);
    EXPECT_EQ(ev[1].command.kind, K::SetBitrate);
    EXPECT_EQ(ev[1].command.value, 6u);
    EXPECT_EQ(ev[1].command.bitrate_bps, 500'000u);
    EXPECT_EQ(ev[2].command.kind, K::Open);
    EXPECT_EQ(ev[3].command.kind, K::SetBtr);
    EXPECT_EQ(ev[3].command.value, 0x031Cu);
    EXPECT_EQ(ev[4].command.kind, K::OpenListenOnly);
    EXPECT_EQ(ev[5].command.kind, K::Status);
    EXPECT_FALSE(ev[5].command.has_value);
    EXPECT_TRUE(ev[6].command.has_value);
    EXPECT_EQ(ev[6].command.value, 0u);
    EXPECT_EQ(ev[8].command.kind, K::Version);
    EXPECT_EQ(ev[8].command.value, 0x1013u);
    EXPECT_EQ(ev[10].command.text, "A1B2");
    EXPECT_EQ(ev[11].command.kind, K::Timestamps);
    EXPECT_EQ(ev[11].command.value, 1u);
    EXPECT_EQ(ev[12].command.kind, K::TransmitAck);
    EXPECT_EQ(ev[13].kind, SlcanEvent::Kind::Ok);
    EXPECT_EQ(ev[14].kind, SlcanEvent::Kind::Error);
    EXPECT_EQ(p.counters().commands, 13u);
    EXPECT_EQ(p.counters().oks, 1u);
    EXPECT_EQ(p.counters().errors, 1u);
}

TEST(Slcan, command_text_round_trips_through_the_parser) {
    EXPECT_EQ(navcan::slcan_open_sequence(500'000), "C\rS6\rO\r");
    EXPECT_EQ(navcan::slcan_open_sequence(1'000'000, true), "C\rS8\rL\r");
    EXPECT_EQ(navcan::slcan_open_sequence(333'000), "");
    EXPECT_EQ(navcan::slcan_bitrate_bps(0), 10'000u);
    EXPECT_EQ(navcan::slcan_bitrate_bps(4), 125'000u);
    EXPECT_FALSE(navcan::slcan_bitrate_bps(9).has_value());
    EXPECT_EQ(navcan::slcan_bitrate_code(800'000), 7);
    const std::vector<std::string> texts = {"S0\r", "s031C\r", "O\r",  "L\r",     "C\r",
                                            "F\r",  "F0A\r",   "V\r",  "V1013\r", "v\r",
                                            "N\r",  "N1234\r", "Z0\r", "Z1\r",    "z\r"};
    for (const auto& t : texts) {
        SlcanEvent ev;
        ASSERT_TRUE(navcan::slcan_parse_line(std::string_view(t).substr(0, t.size() - 1), ev)) << t;
        ASSERT_EQ(ev.kind, SlcanEvent::Kind::Command) << t;
        EXPECT_EQ(navcan::slcan_command_text(ev.command), t);
    }
}

TEST(Slcan, rejects_malformed_lines_and_counts_them) {
    const std::vector<std::string> bad = {
        "t12",         // short
        "t1239",       // DLC 9 (classic only)
        "t1232AA",     // one byte missing
        "t1232AABBC",  // odd digit
        "t8001",       // 11-bit ID > 0x7FF... 3 digits parse, value 0x800
        "tG231AA",     // not hex
        "T1234567",    // short extended
        "T200000000",  // 29-bit ID overflow
        "t1230EA60",   // timestamp 60000 out of range
        "S9",          // no such bitrate
        "Ox",          // trailing text
        "Q",           // unknown command
    };
    for (const auto& b : bad) {
        SlcanEvent ev;
        EXPECT_FALSE(navcan::slcan_parse_line(b, ev)) << b;
    }
    navcan::SlcanParser p;
    std::string all;
    for (const auto& b : bad) all += b + "\r";
    auto ev = parse_all(p, all);
    EXPECT_EQ(ev.size(), 0u);
    EXPECT_EQ(p.counters().malformed, bad.size());
}

TEST(Slcan, resynchronises_after_garbage_for_any_split) {
    std::mt19937 rng(7);
    std::vector<nav::CanFrame> frames;
    std::string clean, dirty;
    const std::string garbage[] = {"xx", "\x01\xFFq", "", "hello world, not slcan at all!!!!!",
                                   "zz9"};
    std::size_t garbage_lines_expected = 0;
    for (int i = 0; i < 200; ++i) {
        std::vector<std::uint8_t> bytes(static_cast<std::size_t>(rng() % 9));
        for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
        const bool ext = (i % 3) == 0;
        const std::uint32_t id = ext ? rng() & 0x1FFF'FFFFu : rng() & 0x7FFu;
        frames.push_back(frame(id, ext, bytes));
        const std::string line = navcan::slcan_encode(frames.back());
        clean += line;
        const std::string& g = garbage[i % 5];
        // Garbage glued to the front of a frame line, or as a line of its own.
        if (i % 2 == 0) {
            dirty += g + line;
        } else {
            dirty += line;
            if (!g.empty() && g != "zz9") {
                dirty += g + "\r";
                ++garbage_lines_expected;
            }
        }
    }
    for (int trial = 0; trial < 20; ++trial) {
        navcan::SlcanParser p;
        std::vector<nav::CanFrame> got;
        std::size_t pos = 0;
        while (pos < dirty.size()) {
            const std::size_t n = std::min<std::size_t>(dirty.size() - pos, 1 + rng() % 40);
            p.feed(std::string_view(dirty).substr(pos, n), [&](const SlcanEvent& e) {
                if (e.kind == SlcanEvent::Kind::Frame) got.push_back(e.frame);
            });
            pos += n;
        }
        ASSERT_EQ(got.size(), frames.size());
        for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(got[i], frames[i]) << i;
        EXPECT_EQ(p.counters().frames, frames.size());
        EXPECT_GT(p.counters().garbage_bytes, 0u);
        EXPECT_EQ(p.counters().malformed, garbage_lines_expected);
    }
    // Byte by byte, clean: identical events, no garbage.
    navcan::SlcanParser p;
    std::size_t n = 0;
    for (char c : clean) p.feed(std::string_view(&c, 1), [&](const SlcanEvent&) { ++n; });
    EXPECT_EQ(n, frames.size());
    EXPECT_EQ(p.counters().garbage_bytes, 0u);
}
