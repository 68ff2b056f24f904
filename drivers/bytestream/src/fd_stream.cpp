// SPDX-License-Identifier: Apache-2.0
#include "fd_stream.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <ctime>
#include <thread>

#include "mirage/hostclock/host_clock.hpp"

namespace mirage::bytestream {

namespace detail {
namespace {

constexpr std::int64_t kFirstBackoffNs =
    std::chrono::duration_cast<std::chrono::nanoseconds>(kReopenBackoffFirst).count();
constexpr std::int64_t kMaxBackoffNs =
    std::chrono::duration_cast<std::chrono::nanoseconds>(kReopenBackoffMax).count();
constexpr std::int64_t kWriteTimeoutNs = 1'000'000'000;

// Waits for `events` on fd until the deadline; >0 ready, 0 timeout, <0 error (not EINTR).
int wait_fd(int fd, short events, std::int64_t deadline_ns, short& revents) {
    while (true) {
        const std::int64_t left =
            std::max<std::int64_t>(0, deadline_ns - hostclock::monotonic_ns());
        timespec ts{static_cast<time_t>(left / 1'000'000'000),
                    static_cast<long>(left % 1'000'000'000)};
        pollfd p{fd, events, 0};
        const int rc = ::ppoll(&p, 1, &ts, nullptr);
        if (rc < 0 && errno == EINTR) continue;
        revents = p.revents;
        return rc;
    }
}

// errno values that mean the device or peer is gone (not a transient condition).
bool is_gone(int err) {
    return err == EIO || err == ENXIO || err == ENODEV || err == ECONNRESET || err == EPIPE ||
           err == ENOTCONN || err == ETIMEDOUT || err == EBADF || err == ESHUTDOWN ||
           err == ECONNABORTED || err == EHOSTUNREACH || err == ENETUNREACH;
}

}  // namespace

std::int64_t deadline_after(std::chrono::nanoseconds timeout) {
    const std::int64_t t = std::clamp<std::int64_t>(timeout.count(), 0, 3'600'000'000'000);
    return hostclock::monotonic_ns() + t;
}

FdStream::FdStream(std::string name, Kind kind, bool reopenable)
    : name_(std::move(name)), kind_(kind), reopenable_(reopenable), backoff_ns_(kFirstBackoffNs) {}

FdStream::~FdStream() {
    if (fd_ >= 0) ::close(fd_);
}

void FdStream::adopt(int fd) {
    fd_ = fd;
    up_ = true;
}

void FdStream::mark_down() {
    std::lock_guard lock(reopen_mutex_);
    if (!up_) return;
    up_ = false;
    ++closes_;
    next_retry_ns_ = hostclock::monotonic_ns() + backoff_ns_;
}

bool FdStream::try_reopen_once() {
    // Caller holds reopen_mutex_.
    const int nfd = reopen_fd();
    if (nfd < 0 || ::dup2(nfd, fd_) < 0) {
        if (nfd >= 0) ::close(nfd);
        ++reopen_failures_;
        backoff_ns_ = std::min(backoff_ns_ * 2, kMaxBackoffNs);
        next_retry_ns_ = hostclock::monotonic_ns() + backoff_ns_;
        return false;
    }
    ::close(nfd);
    backoff_ns_ = kFirstBackoffNs;
    ++reopens_;
    up_ = true;
    return true;
}

bool FdStream::reopen_until(std::int64_t deadline_ns) {
    if (!reopenable_) {
        hostclock::sleep_until_monotonic(
            deadline_ns);  // nothing will come back; do not spin the caller
        return false;
    }
    while (true) {
        std::int64_t retry;
        {
            std::lock_guard lock(reopen_mutex_);
            if (up_) return true;
            if (hostclock::monotonic_ns() >= next_retry_ns_ && try_reopen_once()) return true;
            retry = next_retry_ns_;
        }
        if (retry >= deadline_ns) {
            hostclock::sleep_until_monotonic(deadline_ns);
            return false;
        }
        hostclock::sleep_until_monotonic(retry);
    }
}

long FdStream::read_once(int fd, std::span<std::uint8_t> buffer, std::int64_t& host_ns) {
    const long r = static_cast<long>(::read(fd, buffer.data(), buffer.size()));
    host_ns = hostclock::monotonic_ns();
    return r;
}

ReadStatus FdStream::read(std::span<std::uint8_t> buffer, std::size_t& n, std::int64_t& host_ns,
                          std::chrono::nanoseconds timeout) {
    n = 0;
    host_ns = 0;
    const std::int64_t deadline = deadline_after(timeout);
    while (true) {
        if (!up_ && !reopen_until(deadline)) return ReadStatus::Closed;
        short revents = 0;  // POLLHUP still lets us read what is queued first
        const int rc = wait_fd(fd_, POLLIN, deadline, revents);
        if (rc == 0) return ReadStatus::Timeout;
        if (rc < 0) {
            mark_down();
            return ReadStatus::Closed;
        }
        const long r = read_once(fd_, buffer, host_ns);
        if (r > 0 || (r == 0 && kind_ == Kind::Datagram)) {
            n = static_cast<std::size_t>(r);
            bytes_in_ += n;
            ++reads_;
            return ReadStatus::Data;
        }
        const int err = r < 0 ? errno : 0;
        if (r < 0 && (err == EAGAIN || err == EWOULDBLOCK || err == EINTR)) {
            if (hostclock::monotonic_ns() >= deadline) return ReadStatus::Timeout;
            continue;
        }
        if (kind_ == Kind::Datagram && !is_gone(err)) continue;  // e.g. ECONNREFUSED (ICMP)
        // End of stream, EIO from a pty whose master left, a reset peer, or any other hard
        // error: the device is gone until a reopen succeeds.
        mark_down();
        return ReadStatus::Closed;
    }
}

bool FdStream::write(std::span<const std::uint8_t> bytes) {
    if (!up_) {
        std::unique_lock lock(reopen_mutex_, std::try_to_lock);
        const bool due =
            lock.owns_lock() && reopenable_ && hostclock::monotonic_ns() >= next_retry_ns_;
        if (!up_ && !(due && try_reopen_once())) {
            ++write_failures_;
            return false;
        }
    }
    const std::int64_t deadline = hostclock::monotonic_ns() + kWriteTimeoutNs;
    std::size_t off = 0;
    while (off < bytes.size() || (bytes.empty() && kind_ == Kind::Datagram && off == 0)) {
        const std::size_t want = bytes.size() - off;
        long r;
        if (kind_ == Kind::Tty)
            r = static_cast<long>(::write(fd_, bytes.data() + off, want));
        else
            r = static_cast<long>(::send(fd_, bytes.data() + off, want, MSG_NOSIGNAL));
        if (r >= 0) {
            off += static_cast<std::size_t>(r);
            bytes_out_ += static_cast<std::uint64_t>(r);
            if (kind_ == Kind::Datagram) break;  // one datagram per write
            continue;
        }
        const int err = errno;
        if (err == EINTR) continue;
        if (err == EAGAIN || err == EWOULDBLOCK) {
            short revents = 0;
            if (wait_fd(fd_, POLLOUT, deadline, revents) > 0) continue;
        } else if (kind_ != Kind::Datagram && is_gone(err)) {
            mark_down();
        }
        ++write_failures_;
        return false;
    }
    return true;
}

StreamCounters FdStream::counters() const {
    StreamCounters c;
    c.bytes_in = bytes_in_;
    c.bytes_out = bytes_out_;
    c.reads = reads_;
    c.write_failures = write_failures_;
    c.reopens = reopens_;
    c.closes = closes_;
    c.reopen_failures = reopen_failures_;
    return c;
}

}  // namespace detail
}  // namespace mirage::bytestream
