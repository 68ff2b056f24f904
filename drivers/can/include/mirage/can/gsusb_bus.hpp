// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <memory>
#include <string>

#include "mirage/can/can_bus.hpp"

namespace mirage::can {

struct GsUsbOptions {
    std::uint16_t vendor_id = 0x1d50;  // candleLight default (docs/nav-protocols.md §10.1)
    std::uint16_t product_id = 0x606f;
    std::string serial;  // empty: the first matching device
    std::uint32_t bitrate = 500'000;
    std::uint8_t channel = 0;
    bool listen_only = false;
};

// A gs_usb (candleLight-class) adapter through libusb, no kernel CAN driver needed
// (docs/nav-protocols.md §10.2). Throws IoError ("gsusb 1d50:606f: ...") when no such device exists
// or the start-up sequence fails.
std::unique_ptr<CanBus> open_gsusb(const GsUsbOptions& options);

}  // namespace mirage::can
