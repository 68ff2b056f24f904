// SPDX-License-Identifier: Apache-2.0
// SlcanBus against a scripted peer: the pty master plays the adapter (docs/nav-protocols.md §9).
#include "mirage/can/slcan_bus.hpp"

#include <gtest/gtest.h>

#include <deque>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/can/can_bus.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "test_paths.hpp"

namespace mirage::can {
namespace {

using namespace std::chrono_literals;
using bytestream::ByteStream;
using bytestream::Pty;
using bytestream::ReadStatus;

std::span<const std::uint8_t> bytes_of(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

std::string read_exactly(ByteStream& s, std::size_t want) {
    std::string out;
    std::uint8_t buf[256];
    const auto end = std::chrono::steady_clock::now() + 5s;
    while (out.size() < want && std::chrono::steady_clock::now() < end) {
        std::size_t n = 0;
        std::int64_t t = 0;
        if (s.read(std::span(buf, std::min(sizeof buf, want - out.size())), n, t, 200ms) ==
            ReadStatus::Data)
            out.append(reinterpret_cast<char*>(buf), n);
    }
    return out;
}

bool nothing_more(ByteStream& s) {
    std::uint8_t buf[64];
    std::size_t n = 0;
    std::int64_t t = 0;
    return s.read(buf, n, t, 20ms) == ReadStatus::Timeout;
}

nav::CanFrame frame_607() {  // t6076F8207800CEFF
    nav::CanFrame f;
    f.id = 0x607;
    f.len = 6;
    f.data = {0xF8, 0x20, 0x78, 0x00, 0xCE, 0xFF, 0, 0};
    return f;
}

nav::CanFrame frame_ext() {  // T18FF50E58AABBCCDD11223344
    nav::CanFrame f;
    f.id = 0x18FF50E5;
    f.extended = true;
    f.len = 8;
    f.data = {0xAA, 0xBB, 0xCC, 0xDD, 0x11, 0x22, 0x33, 0x44};
    return f;
}

TEST(SlcanBus, sends_the_slcand_start_up_sequence_byte_exact) {
    struct Case {
        std::string query, expected;
    };
    const Case cases[] = {
        {"", "C\rS6\rO\r"},  // default 500 kbit/s
        {"?bitrate=500000", "C\rS6\rO\r"},
        {"?baud=921600&bitrate=250000", "C\rS5\rO\r"},
        {"?bitrate=1000000", "C\rS8\rO\r"},
        {"?bitrate=10000", "C\rS0\rO\r"},
        {"?bitrate=125000&listen", "C\rS4\rL\r"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.query);
        Pty pty = bytestream::open_pty();
        auto bus = open_can_bus("slcan:" + pty.slave_path + c.query);
        EXPECT_EQ(bus->name(), "slcan:" + pty.slave_path);
        EXPECT_EQ(read_exactly(*pty.master, c.expected.size()), c.expected);
        EXPECT_TRUE(nothing_more(*pty.master));
    }
}

TEST(SlcanBus, frames_cross_the_line_both_ways) {
    Pty pty = bytestream::open_pty();
    auto bus = open_can_bus("slcan:" + pty.slave_path + "?bitrate=500000");
    ASSERT_EQ(read_exactly(*pty.master, 7), "C\rS6\rO\r");

    // Adapter -> host: OK replies to the three commands, then two frames.
    ASSERT_TRUE(
        pty.master->write(bytes_of("\r\r\rt6076F8207800CEFF\rT18FF50E58AABBCCDD11223344\r")));
    nav::CanFrame got;
    std::int64_t host_ns = 0;
    const std::int64_t before = hostclock::monotonic_ns();
    ASSERT_EQ(bus->receive(got, host_ns, 2s), RxStatus::Frame);
    EXPECT_EQ(got, frame_607());
    EXPECT_LE(host_ns, hostclock::monotonic_ns());
    EXPECT_GT(host_ns, before - 1'000'000'000);
    ASSERT_EQ(bus->receive(got, host_ns, 2s), RxStatus::Frame);
    EXPECT_EQ(got, frame_ext());
    EXPECT_EQ(bus->receive(got, host_ns, 20ms), RxStatus::Timeout);

    // Host -> adapter, as `cansend can0 123#DEADBEEF` appears on the line.
    nav::CanFrame f;
    f.id = 0x123;
    f.len = 4;
    f.data = {0xDE, 0xAD, 0xBE, 0xEF, 0, 0, 0, 0};
    ASSERT_TRUE(bus->send(f));
    EXPECT_EQ(read_exactly(*pty.master, 14), "t1234DEADBEEF\r");
    ASSERT_TRUE(bus->send(frame_ext()));
    EXPECT_EQ(read_exactly(*pty.master, 27), "T18FF50E58AABBCCDD11223344\r");
    nav::CanFrame rtr;
    rtr.id = 0x123;
    rtr.rtr = true;
    rtr.len = 0;
    ASSERT_TRUE(bus->send(rtr));
    EXPECT_EQ(read_exactly(*pty.master, 6), "r1230\r");

    nav::CanFrame error;
    error.error = true;
    error.id = err::kBusOff;
    EXPECT_FALSE(bus->send(error));  // slcan has no form for error frames

    const BusCounters c = bus->counters();
    EXPECT_EQ(c.rx_frames, 2u);
    EXPECT_EQ(c.tx_frames, 3u);
    EXPECT_EQ(c.tx_failed, 1u);
    EXPECT_EQ(c.malformed, 0u);
    EXPECT_EQ(c.nacks, 0u);
}

TEST(SlcanBus, resynchronises_after_garbage_and_counts_nacks) {
    Pty pty = bytestream::open_pty();
    auto bus = open_can_bus("slcan:" + pty.slave_path);
    ASSERT_EQ(read_exactly(*pty.master, 7), "C\rS6\rO\r");
    // A bad line (9 bytes + its terminator), garbage glued to a frame (2 bytes), two `\a`
    // error replies, and a line far longer than any slcan line.
    const std::string line = std::string("xyz\x01\x02junk\r") + "t6076F8207800CEFF\r" +
                             "##t1230\r" + "\a\a" + std::string(80, 'Q') + "\r" +
                             "T18FF50E58AABBCCDD11223344\r";
    ASSERT_TRUE(pty.master->write(bytes_of(line)));
    nav::CanFrame got;
    std::int64_t t = 0;
    ASSERT_EQ(bus->receive(got, t, 2s), RxStatus::Frame);
    EXPECT_EQ(got, frame_607());
    ASSERT_EQ(bus->receive(got, t, 2s), RxStatus::Frame);
    EXPECT_EQ(got.id, 0x123u);
    EXPECT_EQ(got.len, 0u);
    ASSERT_EQ(bus->receive(got, t, 2s), RxStatus::Frame);
    EXPECT_EQ(got, frame_ext());
    EXPECT_EQ(bus->receive(got, t, 20ms), RxStatus::Timeout);
    const BusCounters c = bus->counters();
    EXPECT_EQ(c.rx_frames, 3u);
    EXPECT_EQ(c.nacks, 2u);
    EXPECT_EQ(c.malformed, 10u + 2u + 81u);  // every byte not part of a frame or reply
}

TEST(SlcanBus, linux_slcan_state_and_error_lines_become_error_frames) {
    Pty pty = bytestream::open_pty();
    auto bus = open_can_bus("slcan:" + pty.slave_path);
    ASSERT_EQ(read_exactly(*pty.master, 7), "C\rS6\rO\r");
    ASSERT_TRUE(pty.master->write(bytes_of("sw100010\rsp130010\rsb256256\re2ao\rsa000000\r")));
    nav::CanFrame got;
    std::int64_t t = 0;

    ASSERT_EQ(bus->receive(got, t, 2s), RxStatus::ErrorFrame);  // warning, rx 100 tx 10
    EXPECT_TRUE(got.error);
    EXPECT_EQ(got.id, err::kController | err::kCounters);
    EXPECT_EQ(got.data[1], err::kCtrlRxWarning);
    EXPECT_EQ(got.data[6], 10u);
    EXPECT_EQ(got.data[7], 100u);

    ASSERT_EQ(bus->receive(got, t, 2s), RxStatus::ErrorFrame);  // passive, rx 130
    EXPECT_EQ(got.data[1], err::kCtrlRxPassive);

    ASSERT_EQ(bus->receive(got, t, 2s), RxStatus::ErrorFrame);  // bus-off
    EXPECT_EQ(got.id, err::kBusOff | err::kCounters);
    EXPECT_EQ(got.data[6], 255u);  // 256 saturates the one-byte counter
    EXPECT_EQ(got.data[7], 255u);

    ASSERT_EQ(bus->receive(got, t, 2s), RxStatus::ErrorFrame);  // no ack + rx overrun
    EXPECT_EQ(got.id, err::kNoAck | err::kController);
    EXPECT_EQ(got.data[1], err::kCtrlRxOverflow);

    ASSERT_EQ(bus->receive(got, t, 2s), RxStatus::ErrorFrame);  // back to active
    EXPECT_EQ(got.data[1], err::kCtrlActive);

    const BusCounters c = bus->counters();
    EXPECT_EQ(c.error_frames, 5u);
    EXPECT_EQ(c.bus_off, 1u);
    EXPECT_EQ(c.rx_frames, 0u);
    EXPECT_EQ(c.malformed, 0u);
}

// A stream that hands out a script in chunks of chosen sizes, so the bus sees any split.
class ChunkedStream final : public ByteStream {
  public:
    ChunkedStream(std::string script, std::vector<std::size_t> cuts)
        : script_(std::move(script)), cuts_(cuts.begin(), cuts.end()) {}
    // Exhausted: Timeout at once (the script is all there is).
    ReadStatus read(std::span<std::uint8_t> buffer, std::size_t& n, std::int64_t& host_ns,
                    std::chrono::nanoseconds) override {
        n = 0;
        host_ns = hostclock::monotonic_ns();
        if (pos_ >= script_.size()) return ReadStatus::Timeout;
        std::size_t take = cuts_.empty() ? script_.size() - pos_ : cuts_.front();
        if (!cuts_.empty()) cuts_.pop_front();
        take = std::min({take, buffer.size(), script_.size() - pos_});
        std::copy_n(script_.data() + pos_, take, buffer.data());
        pos_ += take;
        n = take;
        return ReadStatus::Data;
    }
    bool write(std::span<const std::uint8_t> bytes) override {
        written.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        return true;
    }
    bytestream::StreamCounters counters() const override { return {}; }
    std::string name() const override { return "chunked"; }
    std::string written;

  private:
    std::string script_;
    std::size_t pos_ = 0;
    std::deque<std::size_t> cuts_;
};

TEST(SlcanBus, any_split_of_the_byte_stream_gives_the_same_frames) {
    const std::string script = std::string("\r\r\a") + "t6076F8207800CEFF\r" + "garbage\r" +
                               "sb256256\r" + "##T18FF50E58AABBCCDD11223344\r" +
                               std::string(40, 'z') + "t1234DEADBEEF\r" + "e1c\r";
    auto collect = [&](std::vector<std::size_t> cuts) {
        auto stream = std::make_unique<ChunkedStream>(script, std::move(cuts));
        auto* raw = stream.get();
        auto bus = open_slcan(std::move(stream), 500'000);
        EXPECT_EQ(raw->written, "C\rS6\rO\r");
        std::vector<std::pair<RxStatus, nav::CanFrame>> out;
        nav::CanFrame f;
        std::int64_t t = 0;
        for (RxStatus st; (st = bus->receive(f, t, 1s)) != RxStatus::Timeout;)
            out.emplace_back(st, f);
        const BusCounters c = bus->counters();
        return std::make_tuple(out, c.nacks, c.malformed, c.bus_off);
    };
    const auto whole = collect({});
    ASSERT_EQ(std::get<0>(whole).size(), 5u);
    EXPECT_EQ(std::get<0>(whole)[0].second, frame_607());
    EXPECT_EQ(std::get<0>(whole)[1].first, RxStatus::ErrorFrame);
    EXPECT_EQ(std::get<0>(whole)[2].second, frame_ext());
    EXPECT_EQ(std::get<0>(whole)[3].second.id, 0x123u);
    EXPECT_EQ(std::get<0>(whole)[4].first, RxStatus::ErrorFrame);
    EXPECT_EQ(std::get<1>(whole), 1u);
    EXPECT_EQ(std::get<2>(whole), 8u + 2u + 40u);
    EXPECT_EQ(std::get<3>(whole), 1u);

    std::mt19937 rng(4);
    std::vector<std::size_t> ones(script.size(), 1);
    EXPECT_EQ(collect(ones), whole);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<std::size_t> cuts;
        for (std::size_t left = script.size(); left > 0;) {
            const std::size_t c = std::min<std::size_t>(left, 1 + rng() % 12);
            cuts.push_back(c);
            left -= c;
        }
        ASSERT_EQ(collect(cuts), whole) << "trial " << trial;
    }
}

// The adapter vanishes (pty destroyed), the bus reports Closed; a new adapter appears behind
// the same symlink and the bus reopens the line and sends the start-up sequence again.
TEST(SlcanBus, reopens_a_vanished_adapter_and_sends_the_open_sequence_again) {
    mirage::test::TempDir dir;
    const std::string link = dir.file("ttyACM-slcan");
    auto point_link_to = [&](const std::string& target) {
        const std::string tmp = link + ".new";
        std::filesystem::remove(tmp);
        std::filesystem::create_symlink(target, tmp);
        std::filesystem::rename(tmp, link);
    };
    auto pty1 = std::make_unique<Pty>(bytestream::open_pty());
    point_link_to(pty1->slave_path);
    auto bus = open_can_bus("slcan:" + link);
    ASSERT_EQ(read_exactly(*pty1->master, 7), "C\rS6\rO\r");
    pty1.reset();
    nav::CanFrame got;
    std::int64_t t = 0;
    EXPECT_EQ(bus->receive(got, t, 2s), RxStatus::Closed);

    Pty pty2 = bytestream::open_pty();
    point_link_to(pty2.slave_path);
    ASSERT_TRUE(pty2.master->write(bytes_of("t6076F8207800CEFF\r")));
    RxStatus st = RxStatus::Closed;
    for (int i = 0; i < 50 && st != RxStatus::Frame; ++i) st = bus->receive(got, t, 200ms);
    ASSERT_EQ(st, RxStatus::Frame);
    EXPECT_EQ(got, frame_607());
    EXPECT_EQ(read_exactly(*pty2.master, 7), "C\rS6\rO\r");
}

}  // namespace
}  // namespace mirage::can
