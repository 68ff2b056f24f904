// SPDX-License-Identifier: Apache-2.0
// Serial streams over ptys: raw round trips, termios framing, and reopen after the device vanishes.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "mirage/bytestream/byte_stream.hpp"
#include "mirage/hostclock/host_clock.hpp"
#include "stream_test_util.hpp"
#include "test_paths.hpp"

namespace mirage::bytestream {
namespace {

using namespace std::chrono_literals;
using test::bytes_of;
using test::read_exactly;

std::string all_byte_values() {
    std::string s;
    for (int i = 0; i < 256; ++i) s.push_back(static_cast<char>(i));
    return s;
}

// The termios of the tty behind `path`, read through a descriptor of our own (termios belongs
// to the tty, so it shows what the stream under test set).
termios termios_of(const std::string& path) {
    termios tio{};
    const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    EXPECT_GE(fd, 0) << path;
    if (fd >= 0) {
        EXPECT_EQ(::tcgetattr(fd, &tio), 0);
        ::close(fd);
    }
    return tio;
}

TEST(PtyStream, round_trips_every_byte_value_at_several_bauds) {
    struct Case {
        std::string query;
        speed_t speed;
        bool two_stop;
    };
    const Case cases[] = {
        {"?baud=9600", B9600, false},
        {"?baud=115200&bits=8&parity=none&stop=1", B115200, false},
        {"?baud=460800&parity=even", B460800, false},
        {"?baud=921600&parity=odd&stop=2", B921600, true},
        {"", B115200, false},  // defaults
    };
    const std::string payload = all_byte_values();  // \r \n ^C ^S ... must pass unchanged
    for (const auto& c : cases) {
        SCOPED_TRACE(c.query);
        Pty pty = open_pty();
        auto serial = open_byte_stream(pty.slave_path + c.query);
        EXPECT_EQ(serial->name(), "serial:" + pty.slave_path);

        const termios tio = termios_of(pty.slave_path);
        EXPECT_EQ(cfgetospeed(&tio), c.speed);
        EXPECT_EQ(cfgetispeed(&tio), c.speed);
        // The Linux pty driver keeps CS8 and clears PARENB/PARODD whatever is asked (a pty has
        // no line); speed and stop bits are stored, so those are what a pty can show.
        EXPECT_EQ((tio.c_cflag & CSTOPB) != 0, c.two_stop);
        EXPECT_EQ(tio.c_lflag & (ICANON | ECHO | ISIG), 0u);
        EXPECT_EQ(tio.c_oflag & OPOST, 0u);

        ASSERT_TRUE(pty.master->write(bytes_of(payload)));
        EXPECT_EQ(read_exactly(*serial, payload.size()), payload);
        ASSERT_TRUE(serial->write(bytes_of(payload)));
        EXPECT_EQ(read_exactly(*pty.master, payload.size()), payload);

        const StreamCounters sc = serial->counters();
        EXPECT_EQ(sc.bytes_in, 256u);
        EXPECT_EQ(sc.bytes_out, 256u);
        EXPECT_GE(sc.reads, 1u);
        EXPECT_EQ(sc.write_failures, 0u);
        EXPECT_EQ(sc.reopens, 0u);
    }
}

TEST(PtyStream, seven_bit_framing_carries_ascii_nmea) {
    Pty pty = open_pty();
    auto serial = open_byte_stream("serial:" + pty.slave_path + "?baud=4800&bits=7&parity=even");
    const termios tio = termios_of(pty.slave_path);
    EXPECT_EQ(cfgetospeed(&tio), static_cast<speed_t>(B4800));
    const std::string line =
        "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n";
    ASSERT_TRUE(pty.master->write(bytes_of(line)));
    EXPECT_EQ(read_exactly(*serial, line.size()), line);
}

TEST(PtyStream, read_times_out_with_nothing_written) {
    Pty pty = open_pty();
    auto serial = open_byte_stream(pty.slave_path);
    std::uint8_t buf[16];
    std::size_t n = 99;
    std::int64_t host_ns = -1;
    EXPECT_EQ(serial->read(buf, n, host_ns, 20ms), ReadStatus::Timeout);
    EXPECT_EQ(n, 0u);
    // Bytes written before the read are there; host_ns is a CLOCK_MONOTONIC reading.
    const std::int64_t before = hostclock::monotonic_ns();
    ASSERT_TRUE(pty.master->write(bytes_of("x")));
    ASSERT_EQ(serial->read(buf, n, host_ns, 2s), ReadStatus::Data);
    EXPECT_EQ(n, 1u);
    EXPECT_EQ(buf[0], 'x');
    EXPECT_GE(host_ns, before);
    EXPECT_LE(host_ns, hostclock::monotonic_ns());
}

TEST(PtyStream, bytes_written_before_the_reader_opens_wait_for_it) {
    Pty pty = open_pty();
    ASSERT_TRUE(pty.master->write(bytes_of("early")));
    auto serial = open_byte_stream(pty.slave_path);
    EXPECT_EQ(read_exactly(*serial, 5), "early");
}

// Reopen: the reader opens a symlink (like /dev/serial/by-id/...); the test destroys the pty
// (the device vanishes: the reader sees EIO/hang-up -> Closed), creates a new pty and re-points
// the symlink atomically (rename over it), as udev does when an adapter is re-plugged. The
// reader's next reads retry with backoff and find the new device.
TEST(PtyStream, reopens_after_the_device_vanishes_and_reappears_behind_a_symlink) {
    mirage::test::TempDir dir;
    const std::string link = dir.file("ins-serial");
    auto point_link_to = [&](const std::string& target) {
        const std::string tmp = link + ".new";
        std::filesystem::remove(tmp);
        std::filesystem::create_symlink(target, tmp);
        std::filesystem::rename(tmp, link);
    };

    auto pty1 = std::make_unique<Pty>(open_pty());
    point_link_to(pty1->slave_path);
    auto serial = open_byte_stream(link + "?baud=115200");
    ASSERT_TRUE(pty1->master->write(bytes_of("one")));
    EXPECT_EQ(read_exactly(*serial, 3), "one");

    pty1.reset();  // the device vanishes
    std::uint8_t buf[64];
    std::size_t n = 0;
    std::int64_t host_ns = 0;
    EXPECT_EQ(serial->read(buf, n, host_ns, 2s), ReadStatus::Closed);
    EXPECT_EQ(serial->counters().closes, 1u);
    EXPECT_FALSE(serial->write(bytes_of("lost")));  // no device: refused and counted
    EXPECT_EQ(serial->counters().write_failures, 1u);

    // Still gone: reads wait out their deadline retrying (100 ms, then 200 ms ...), say Closed.
    EXPECT_EQ(serial->read(buf, n, host_ns, 350ms), ReadStatus::Closed);
    const auto failed = serial->counters().reopen_failures;
    EXPECT_GE(failed, 1u);
    EXPECT_LE(failed, 2u);
    EXPECT_EQ(serial->counters().reopens, 0u);

    Pty pty2 = open_pty();
    point_link_to(pty2.slave_path);
    ASSERT_TRUE(pty2.master->write(bytes_of("two")));
    EXPECT_EQ(read_exactly(*serial, 3, std::chrono::seconds(10)), "two");
    EXPECT_EQ(serial->counters().reopens, 1u);
    EXPECT_EQ(serial->counters().closes, 1u);
    ASSERT_TRUE(serial->write(bytes_of("back")));
    EXPECT_EQ(read_exactly(*pty2.master, 4), "back");
}

TEST(PtyStream, master_survives_readers_coming_and_going) {
    Pty pty = open_pty();
    for (int round = 0; round < 3; ++round) {
        auto serial = open_byte_stream(pty.slave_path);
        std::string msg = "r";
        msg += std::to_string(round);
        ASSERT_TRUE(serial->write(bytes_of(msg)));
        EXPECT_EQ(read_exactly(*pty.master, msg.size()), msg);
    }
    std::uint8_t buf[8];
    std::size_t n = 0;
    std::int64_t host_ns = 0;
    EXPECT_EQ(pty.master->read(buf, n, host_ns, 20ms), ReadStatus::Timeout);
    EXPECT_EQ(pty.master->counters().closes, 0u);
}

}  // namespace
}  // namespace mirage::bytestream
