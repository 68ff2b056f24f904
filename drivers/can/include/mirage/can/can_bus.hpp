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
};

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

// Opens a bus from a spec (see README "CAN buses"):
//   socketcan:<ifname>
//   slcan:<serial device>[?baud=115200&bitrate=500000]
//   gsusb:<vid>:<pid>[?bitrate=500000&serial=<usb serial>]
//   memory:<name>          (in-process; every bus opened with the same name sees the others' frames)
// Throws ConfigError on a malformed spec, IoError when the device cannot be opened.
std::unique_ptr<CanBus> open_can_bus(const std::string& spec);

}  // namespace mirage::can
