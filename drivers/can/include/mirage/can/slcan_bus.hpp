// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "mirage/can/can_bus.hpp"

namespace mirage::bytestream {
class ByteStream;
}

namespace mirage::can {

struct SlcanOptions {
    std::string device;               // serial port or pty path
    std::uint32_t baud = 115'200;     // serial line speed (USB-CDC adapters ignore it)
    std::uint32_t bitrate = 500'000;  // CAN bitrate -> `Sn` (docs/nav-protocols.md §9)
    bool listen_only = false;         // `L` instead of `O`
};

// slcan (Lawicel ASCII) over a serial line, like `slcand -o -c -s<n>`: at open it sends
// `C\rS<n>\rO\r` (no reply is awaited: adapters answer `\a` to `C` on a closed channel).
// Received lines go through mirage::navcan's SlcanParser: frames are delivered, `\r` replies
// ignored, `\a` replies counted in `nacks`, bad lines counted in `malformed`. Linux slcan state
// lines (`sb256256`: bus-off, `sp`/`sw`/`sa` passive/warning/active with rx/tx error counts)
// and error lines (`e1a`...) become error frames with SocketCAN's CAN_ERR_* layout (bus-off
// also counted in bus_off). If the line vanishes, receive() reports Closed and the serial
// stream reopens itself with backoff; the open sequence is then sent again.
// Throws ConfigError for a bitrate without an `Sn` code, IoError naming the device.
std::unique_ptr<CanBus> open_slcan(const SlcanOptions& options);
// The same over an already open stream (tests; slcan over TCP with a serial server).
std::unique_ptr<CanBus> open_slcan(std::unique_ptr<bytestream::ByteStream> stream,
                                   std::uint32_t bitrate, bool listen_only = false);

}  // namespace mirage::can
