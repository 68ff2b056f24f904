// SPDX-License-Identifier: Apache-2.0
#pragma once
// A ByteStream over one POSIX descriptor with deadline reads (ppoll) and reopen-with-backoff.
// Plain POSIX rather than Boost.Asio: the interface is a blocking read with a per-call deadline,
// which poll expresses directly, while Asio's synchronous reads have no timeout (we would need
// an io_context, async_read and run_for per call); termios, openpty and SO_TIMESTAMPNS are
// POSIX calls in either case.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include "mirage/bytestream/byte_stream.hpp"

namespace mirage::bytestream::detail {

class FdStream : public ByteStream {
  public:
    ~FdStream() override;

    ReadStatus read(std::span<std::uint8_t> buffer, std::size_t& n, std::int64_t& host_ns,
                    std::chrono::nanoseconds timeout) override;
    bool write(std::span<const std::uint8_t> bytes) override;
    StreamCounters counters() const override;
    std::string name() const override { return name_; }

  protected:
    enum class Kind : std::uint8_t { Tty, Stream, Datagram };
    // `reopenable`: a vanished device / departed peer is reopened; otherwise it stays Closed.
    FdStream(std::string name, Kind kind, bool reopenable);
    // Takes the first descriptor (from the subclass constructor, after a successful open).
    void adopt(int fd);
    // Opens a fresh descriptor for a reopen, or returns -1 (errno set). Never throws.
    virtual int reopen_fd() { return -1; }
    // One non-blocking read from `fd`; the default is ::read with host_ns = now. Returns what
    // ::read returns (0 = end of stream unless the kind is Datagram).
    virtual long read_once(int fd, std::span<std::uint8_t> buffer, std::int64_t& host_ns);
    int fd() const { return fd_; }
    void mark_down();

  private:
    bool reopen_until(std::int64_t deadline_ns);
    bool try_reopen_once();

    std::string name_;
    Kind kind_;
    bool reopenable_;
    // The descriptor number never changes after adopt(): a reopen dup2()s the new file onto it,
    // and a dead device stays open until then, so a concurrent reader and writer never see a
    // closed or reused number.
    int fd_ = -1;
    std::atomic<bool> up_{false};
    std::mutex reopen_mutex_;
    std::int64_t next_retry_ns_ = 0;  // guarded by reopen_mutex_
    std::int64_t backoff_ns_ = 0;     // guarded by reopen_mutex_

    std::atomic<std::uint64_t> bytes_in_{0}, bytes_out_{0}, reads_{0}, write_failures_{0},
        reopens_{0}, closes_{0}, reopen_failures_{0};
};

// ns of a steady-clock duration, saturated to a sane deadline.
std::int64_t deadline_after(std::chrono::nanoseconds timeout);

}  // namespace mirage::bytestream::detail
