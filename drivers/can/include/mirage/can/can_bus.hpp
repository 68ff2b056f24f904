// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "mirage/nav/can_frame.hpp"

namespace mirage::can {

enum class RxStatus : std::uint8_t {
    Frame,       // `out` holds a data frame
    ErrorFrame,  // `out` holds an error frame (bus error, controller state change, bus-off)
    Timeout,     // nothing arrived before the deadline
    Closed,      // the device went away or the bus was closed; the caller may reopen
};

struct BusCounters {
    std::uint64_t rx_frames = 0;
    std::uint64_t tx_frames = 0;
    std::uint64_t tx_failed = 0;     // send() returned false
    std::uint64_t error_frames = 0;  // error frames received
    std::uint64_t bus_off = 0;       // bus-off events reported by the controller
    std::uint64_t malformed = 0;     // bytes from the device that were not a valid frame
    std::uint64_t nacks = 0;         // the device refused a command or frame (slcan `\a`)
    std::uint64_t rx_overruns = 0;   // frames dropped because the receive queue was full
};

// SocketCAN error-frame layout (linux/can/error.h), used by every backend for error frames:
// CanFrame::id holds the class bits, data[1] the controller state, data[2] the protocol error
// type, data[6]/data[7] the tx/rx error counters; len 8.
namespace err {
inline constexpr std::uint32_t kTxTimeout = 0x001;
inline constexpr std::uint32_t kLostArbitration = 0x002;
inline constexpr std::uint32_t kController = 0x004;  // data[1]: kCtrl* bits
inline constexpr std::uint32_t kProtocol = 0x008;    // data[2]: kProt* bits
inline constexpr std::uint32_t kTransceiver = 0x010;
inline constexpr std::uint32_t kNoAck = 0x020;
inline constexpr std::uint32_t kBusOff = 0x040;
inline constexpr std::uint32_t kBusError = 0x080;
inline constexpr std::uint32_t kRestarted = 0x100;
inline constexpr std::uint32_t kCounters = 0x200;  // data[6] tx, data[7] rx error counts
inline constexpr std::uint8_t kCtrlRxOverflow = 0x01;
inline constexpr std::uint8_t kCtrlTxOverflow = 0x02;
inline constexpr std::uint8_t kCtrlRxWarning = 0x04;
inline constexpr std::uint8_t kCtrlTxWarning = 0x08;
inline constexpr std::uint8_t kCtrlRxPassive = 0x10;
inline constexpr std::uint8_t kCtrlTxPassive = 0x20;
inline constexpr std::uint8_t kCtrlActive = 0x40;
inline constexpr std::uint8_t kProtBit = 0x01;
inline constexpr std::uint8_t kProtForm = 0x02;
inline constexpr std::uint8_t kProtStuff = 0x04;
inline constexpr std::uint8_t kProtBit0 = 0x08;
inline constexpr std::uint8_t kProtBit1 = 0x10;
inline constexpr std::uint8_t kProtOverload = 0x20;
}  // namespace err

// One CAN bus, whatever carries it (SocketCAN, slcan, gs_usb, in-memory). Never throws after
// construction: send/receive report a status and count it. Construction (open) throws
// mirage::IoError / ConfigError naming the backend and the device.
class CanBus {
  public:
    virtual ~CanBus() = default;
    // Queues one frame for transmission; false (counted) if the device refused it.
    virtual bool send(const nav::CanFrame& frame) = 0;
    // Waits up to `timeout` for the next frame. `host_ns` receives the CLOCK_MONOTONIC time the
    // frame was read (for latency figures).
    virtual RxStatus receive(nav::CanFrame& out, std::int64_t& host_ns,
                             std::chrono::nanoseconds timeout) = 0;
    virtual BusCounters counters() const = 0;
    // "socketcan:can0", "slcan:/dev/pts/3", "gsusb:1d50:606f", "memory:bench".
    virtual std::string name() const = 0;
};

// Opens a bus from a spec (docs/live-navigation.md §2):
//   socketcan:<ifname>
//   slcan:<serial device>[?baud=115200&bitrate=500000]
//   gsusb:<vid>:<pid>[?bitrate=500000&serial=<usb serial>]
//   memory:<name>          (in-process; every bus opened with the same name sees the others'
//   frames) slcan also takes `listen` (open listen-only); gsusb also `channel=<n>` and `listen`.
// Throws ConfigError on a malformed spec, IoError when the device cannot be opened.
std::unique_ptr<CanBus> open_can_bus(const std::string& spec);

}  // namespace mirage::can
