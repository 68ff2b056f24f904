// SPDX-License-Identifier: Apache-2.0
// Serial ports and ptys: termios raw mode with the URI's baud and framing (docs/nav-protocols.md
// §13.1).
#include <fcntl.h>
#include <fmt/format.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <utility>

#include "fd_stream.hpp"
#include "mirage/core/error.hpp"
#include "streams.hpp"

namespace mirage::bytestream::detail {
namespace {

struct BaudCode {
    std::uint32_t baud;
    speed_t code;
};
constexpr std::array<BaudCode, 23> kBauds{{
    {300, B300},         {600, B600},         {1200, B1200},       {2400, B2400},
    {4800, B4800},       {9600, B9600},       {19200, B19200},     {38400, B38400},
    {57600, B57600},     {115200, B115200},   {230400, B230400},   {460800, B460800},
    {500000, B500000},   {576000, B576000},   {921600, B921600},   {1000000, B1000000},
    {1152000, B1152000}, {1500000, B1500000}, {2000000, B2000000}, {2500000, B2500000},
    {3000000, B3000000}, {3500000, B3500000}, {4000000, B4000000},
}};

speed_t speed_code(std::uint32_t baud) {
    for (const auto& b : kBauds)
        if (b.baud == baud) return b.code;
    return B0;
}

// Raw mode (no echo, no line editing, no CR/NL mapping, 8 bits through) plus the framing.
bool configure_tty(int fd, const SerialOptions& o) {
    termios tio{};
    if (::tcgetattr(fd, &tio) != 0) return false;
    ::cfmakeraw(&tio);
    tio.c_cflag &= ~static_cast<tcflag_t>(CSIZE | PARENB | PARODD | CSTOPB | CRTSCTS);
    tio.c_cflag |= CLOCAL | CREAD;
    switch (o.bits) {
        case 5:
            tio.c_cflag |= CS5;
            break;
        case 6:
            tio.c_cflag |= CS6;
            break;
        case 7:
            tio.c_cflag |= CS7;
            break;
        default:
            tio.c_cflag |= CS8;
            break;
    }
    if (o.parity != Parity::None) tio.c_cflag |= PARENB;
    if (o.parity == Parity::Odd) tio.c_cflag |= PARODD;
    if (o.stop == 2) tio.c_cflag |= CSTOPB;
    tio.c_cc[VMIN] = 1;
    tio.c_cc[VTIME] = 0;
    const speed_t speed = speed_code(o.baud);
    if (::cfsetispeed(&tio, speed) != 0 || ::cfsetospeed(&tio, speed) != 0) return false;
    return ::tcsetattr(fd, TCSANOW, &tio) == 0;
}

// -1 with errno set on failure; `what` names the failing step.
int open_tty(const SerialOptions& o, const char*& what) {
    what = "open";
    const int fd = ::open(o.path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return -1;
    what = "configure (not a terminal?)";
    if (!configure_tty(fd, o)) {
        const int err = errno;
        ::close(fd);
        errno = err;
        return -1;
    }
    return fd;
}

class SerialStream final : public FdStream {
  public:
    explicit SerialStream(SerialOptions o)
        : FdStream("serial:" + o.path, Kind::Tty, true), options_(std::move(o)) {
        const char* what = "";
        const int fd = open_tty(options_, what);
        if (fd < 0)
            throw IoError(
                fmt::format("serial '{}': {}: {}", options_.path, what, std::strerror(errno)));
        adopt(fd);
    }

  protected:
    int reopen_fd() override {
        const char* what = "";
        return open_tty(options_, what);
    }

  private:
    SerialOptions options_;
};

// The master end of a pty. It holds a slave descriptor of its own so readers can come and go
// without the master seeing a hang-up (and so bytes written before a reader opens wait).
class PtyMaster final : public FdStream {
  public:
    PtyMaster(int master, int slave, const std::string& slave_path)
        : FdStream("pty:" + slave_path, Kind::Tty, false), slave_(slave) {
        adopt(master);
    }
    ~PtyMaster() override { ::close(slave_); }

  private:
    int slave_;
};

}  // namespace

bool serial_baud_supported(std::uint32_t baud) { return speed_code(baud) != B0; }

std::unique_ptr<ByteStream> open_serial(const SerialOptions& options) {
    return std::make_unique<SerialStream>(options);
}

}  // namespace mirage::bytestream::detail

namespace mirage::bytestream {

Pty open_pty() {
    int master = -1, slave = -1;
    if (::openpty(&master, &slave, nullptr, nullptr, nullptr) != 0)
        throw IoError(fmt::format("pty: openpty: {}", std::strerror(errno)));
    auto fail = [&](const char* what) {
        const int err = errno;
        ::close(master);
        ::close(slave);
        throw IoError(fmt::format("pty: {}: {}", what, std::strerror(err)));
    };
    std::array<char, 128> name{};
    if (::ttyname_r(slave, name.data(), name.size()) != 0) fail("ttyname_r");
    // Raw on the slave side sets the line discipline of the pair: bytes pass unchanged.
    detail::SerialOptions raw;
    raw.path = name.data();
    if (!detail::configure_tty(slave, raw)) fail("tcsetattr");
    for (int fd : {master, slave}) {
        const int fl = ::fcntl(fd, F_GETFL);
        if (fl < 0 || ::fcntl(fd, F_SETFL, fl | O_NONBLOCK) != 0) fail("fcntl O_NONBLOCK");
        if (::fcntl(fd, F_SETFD, FD_CLOEXEC) != 0) fail("fcntl FD_CLOEXEC");
    }
    Pty pty;
    pty.slave_path = name.data();
    pty.master = std::make_unique<detail::PtyMaster>(master, slave, pty.slave_path);
    return pty;
}

}  // namespace mirage::bytestream
