// SPDX-License-Identifier: Apache-2.0
// SocketCAN backend: one raw AF_CAN socket bound to one interface (docs/nav-protocols.md §7,
// §13.4).
#include "mirage/can/socketcan_bus.hpp"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <string>

#include "mirage/core/error.hpp"
#include "mirage/hostclock/host_clock.hpp"

namespace mirage::can {
namespace {

// "No such device (ENODEV)": the message and the symbolic name, so logs are greppable.
std::string errno_text(int err) {
    const char* name = ::strerrorname_np(err);
    return std::string(std::strerror(err)) + " (" + (name ? name : std::to_string(err)) + ")";
}

// Errors after which the socket no longer delivers frames from the bus until it is reopened:
// the interface went down (ENETDOWN) or was removed (ENODEV, the kernel also unbinds the socket).
bool is_closed_errno(int err) {
    return err == ENETDOWN || err == ENODEV || err == ENXIO || err == EBADF || err == ENOTCONN;
}

class SocketCanBus final : public CanBus {
  public:
    SocketCanBus(int fd, std::string ifname) : fd_(fd), ifname_(std::move(ifname)) {}
    ~SocketCanBus() override { ::close(fd_); }
    SocketCanBus(const SocketCanBus&) = delete;
    SocketCanBus& operator=(const SocketCanBus&) = delete;

    bool send(const nav::CanFrame& frame) override {
        // Error frames are produced by controllers, not sent; identifiers must fit their width.
        const std::uint32_t max_id = frame.extended ? CAN_EFF_MASK : CAN_SFF_MASK;
        if (frame.error || frame.len > CAN_MAX_DLEN || frame.id > max_id) {
            ++tx_failed_;
            return false;
        }
        can_frame raw{};
        raw.can_id = frame.id;
        if (frame.extended) raw.can_id |= CAN_EFF_FLAG;
        if (frame.rtr) raw.can_id |= CAN_RTR_FLAG;
        raw.len = frame.len;
        if (!frame.rtr) std::copy_n(frame.data.begin(), frame.len, raw.data);
        // The socket is non-blocking: a full queue (ENOBUFS/EAGAIN) is a counted failure, never
        // a stall of the caller's real-time loop.
        ssize_t n = -1;
        do {
            n = ::write(fd_, &raw, sizeof raw);
        } while (n < 0 && errno == EINTR);
        if (n != static_cast<ssize_t>(sizeof raw)) {
            ++tx_failed_;
            return false;
        }
        ++tx_frames_;
        return true;
    }

    RxStatus receive(nav::CanFrame& out, std::int64_t& host_ns,
                     std::chrono::nanoseconds timeout) override {
        // Clamped so that nanoseconds::max() means "wait (practically) forever", not overflow.
        const std::int64_t wait_ns = std::clamp<std::int64_t>(
            static_cast<std::int64_t>(timeout.count()), 0, std::int64_t{1} << 62);
        const std::int64_t deadline = hostclock::monotonic_ns() + wait_ns;
        for (;;) {
            can_frame raw{};
            const ssize_t n = ::read(fd_, &raw, sizeof raw);
            if (n == static_cast<ssize_t>(sizeof raw)) {
                host_ns = hostclock::monotonic_ns();
                return convert(raw, out);
            }
            const int err = n < 0 ? errno : 0;
            if (err == EINTR) continue;
            if (n < 0 && is_closed_errno(err)) return RxStatus::Closed;
            const bool drained = n < 0 && (err == EAGAIN || err == EWOULDBLOCK);
            // Only classic frames are enabled (no CAN_RAW_FD_FRAMES), so a short read cannot
            // come from the bus; it and any other socket error are counted, and the deadline
            // still holds.
            if (!drained) ++malformed_;
            const std::int64_t left = deadline - hostclock::monotonic_ns();
            if (left <= 0) return RxStatus::Timeout;
            if (!drained) continue;
            pollfd pfd{fd_, POLLIN, 0};
            const timespec ts{static_cast<time_t>(left / 1'000'000'000),
                              static_cast<long>(left % 1'000'000'000)};
            const int r = ::ppoll(&pfd, 1, &ts, nullptr);
            if (r < 0 && errno != EINTR) return RxStatus::Closed;
            if (r > 0 && (pfd.revents & (POLLHUP | POLLNVAL)) != 0) return RxStatus::Closed;
            // POLLIN or POLLERR: the next read returns the frame or the pending socket error.
        }
    }

    BusCounters counters() const override {
        BusCounters c;
        c.rx_frames = rx_frames_.load();
        c.tx_frames = tx_frames_.load();
        c.tx_failed = tx_failed_.load();
        c.error_frames = error_frames_.load();
        c.bus_off = bus_off_.load();
        c.malformed = malformed_.load();
        return c;
    }

    std::string name() const override { return "socketcan:" + ifname_; }

  private:
    RxStatus convert(const can_frame& raw, nav::CanFrame& out) {
        out = nav::CanFrame{};
        out.len = std::min<std::uint8_t>(raw.len, CAN_MAX_DLEN);
        std::copy_n(raw.data, out.len, out.data.begin());
        if ((raw.can_id & CAN_ERR_FLAG) != 0) {
            // Error frame (linux/can/error.h): the id holds the error class bits, the data
            // bytes the details (controller state, protocol violation, ...).
            out.error = true;
            out.id = raw.can_id & CAN_ERR_MASK;
            ++error_frames_;
            if ((out.id & CAN_ERR_BUSOFF) != 0) ++bus_off_;
            return RxStatus::ErrorFrame;
        }
        out.extended = (raw.can_id & CAN_EFF_FLAG) != 0;
        out.rtr = (raw.can_id & CAN_RTR_FLAG) != 0;
        out.id = raw.can_id & (out.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
        if (out.rtr) out.data = {};
        ++rx_frames_;
        return RxStatus::Frame;
    }

    int fd_;
    std::string ifname_;
    // send() and receive() may run on different threads; counters() on a third.
    std::atomic<std::uint64_t> rx_frames_{0};
    std::atomic<std::uint64_t> tx_frames_{0};
    std::atomic<std::uint64_t> tx_failed_{0};
    std::atomic<std::uint64_t> error_frames_{0};
    std::atomic<std::uint64_t> bus_off_{0};
    std::atomic<std::uint64_t> malformed_{0};
};

// Closes the descriptor unless released (open_socketcan throws between socket() and return).
struct FdGuard {
    int fd;
    ~FdGuard() {
        if (fd >= 0) ::close(fd);
    }
};

}  // namespace

std::unique_ptr<CanBus> open_socketcan(const std::string& ifname) {
    const std::string who = "socketcan '" + ifname + "': ";
    if (ifname.empty() || ifname.size() >= IFNAMSIZ)
        throw ConfigError(who + "an interface name has 1 to " + std::to_string(IFNAMSIZ - 1) +
                          " characters");

    FdGuard guard{::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW)};
    if (guard.fd < 0) {
        const int err = errno;
        if (err == EAFNOSUPPORT)
            throw IoError(who + "this kernel has no AF_CAN: socket(PF_CAN, SOCK_RAW, CAN_RAW) " +
                          "failed: " + errno_text(err) +
                          "; load the can and can-raw modules, or use slcan: or gsusb:");
        throw IoError(who + "socket(PF_CAN, SOCK_RAW, CAN_RAW) failed: " + errno_text(err));
    }

    const unsigned index = ::if_nametoindex(ifname.c_str());
    if (index == 0) {
        const int err = errno;
        throw IoError(who + "no such interface: " + errno_text(err));
    }

    // Every error class (bus-off, controller state, protocol, ...) arrives as an error frame.
    const can_err_mask_t err_mask = CAN_ERR_MASK;
    if (::setsockopt(guard.fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask, sizeof err_mask) != 0) {
        const int err = errno;
        throw IoError(who + "setsockopt(CAN_RAW_ERR_FILTER) failed: " + errno_text(err));
    }

    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(index);
    if (::bind(guard.fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
        const int err = errno;
        // A non-CAN interface (lo, eth0) is refused with ENODEV.
        throw IoError(who + "bind failed: " + errno_text(err) + " (is it a CAN interface?)");
    }

    auto bus = std::make_unique<SocketCanBus>(guard.fd, ifname);
    guard.fd = -1;
    return bus;
}

}  // namespace mirage::can
