// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace mirage::bytestream {

enum class ReadStatus : std::uint8_t {
    Data,     // `n` bytes were read
    Timeout,  // nothing before the deadline
    Closed,   // peer or device gone; the stream reopens by itself on the next read (with backoff)
};

struct StreamCounters {
    std::uint64_t bytes_in = 0;
    std::uint64_t bytes_out = 0;
    std::uint64_t reads = 0;
    std::uint64_t write_failures = 0;
    std::uint64_t reopens = 0;  // successful reopen after the device vanished or the peer left
    std::uint64_t closes = 0;   // times the device vanished or the peer left (read/write saw it)
    std::uint64_t reopen_failures = 0;  // reopen attempts that failed (then backoff doubles)
};

// A byte stream from a navigation source or to a device: a serial port (or pty), a TCP client,
// a UDP socket (each datagram delivered whole). Reads and writes never throw after open; they
// return a status and count it. A serial device or TCP peer that vanishes is reopened with
// exponential backoff (100 ms doubling to 5 s) inside read().
class ByteStream {
  public:
    virtual ~ByteStream() = default;
    // Waits up to `timeout` for bytes. `host_ns`: CLOCK_MONOTONIC time of the read (UDP: the
    // kernel receive time converted to CLOCK_MONOTONIC).
    virtual ReadStatus read(std::span<std::uint8_t> buffer, std::size_t& n, std::int64_t& host_ns,
                            std::chrono::nanoseconds timeout) = 0;
    // Writes all bytes (blocking up to 1 s); false (counted) on failure.
    virtual bool write(std::span<const std::uint8_t> bytes) = 0;
    virtual StreamCounters counters() const = 0;
    virtual std::string name() const = 0;
    // The local port of a TCP/UDP socket (what `udp://:0` bound to); 0 for serial ports.
    virtual std::uint16_t local_port() const { return 0; }
};

// Transport URIs (docs/live-navigation.md §2):
//   /dev/ttyUSB0?baud=115200[&bits=8&parity=none&stop=1]   serial port or pty (raw mode)
//   serial:/dev/ttyUSB0?baud=…                             same
//   tcp://host:port                                        TCP client
//   udp://[bind-host]:port                                 UDP receiver (port 0: ephemeral)
//   udp://host:port?send                                   UDP sender
// Throws ConfigError on a malformed URI, IoError if the first open fails.
// Serial defaults: baud 115200, bits 8, parity none (also even/odd), stop 1 (or 2).
std::unique_ptr<ByteStream> open_byte_stream(const std::string& uri);

// Reopen backoff after a device vanished or a peer left: 100 ms, doubling, capped at 5 s.
inline constexpr std::chrono::milliseconds kReopenBackoffFirst{100};
inline constexpr std::chrono::milliseconds kReopenBackoffMax{5000};

// A pseudo-terminal pair for tests and the fake INS: the master end as a ByteStream, and the
// path of the slave end ("/dev/pts/N") that a reader opens like a serial port. Both ends are
// raw. The master keeps a slave descriptor of its own open, so it never sees a hang-up while
// readers come and go, and bytes written before a reader opens the slave wait for it.
// Destroying `master` removes the pair (readers then see Closed). Throws IoError.
struct Pty {
    std::unique_ptr<ByteStream> master;
    std::string slave_path;
};
Pty open_pty();

}  // namespace mirage::bytestream
