// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>

namespace mirage::nav {

// One classic CAN 2.0 frame (INS CAN outputs never use CAN FD: docs/nav-protocols.md §7.3).
struct CanFrame {
    std::uint32_t id = 0;   // 11-bit or 29-bit identifier, without flag bits
    bool extended = false;  // 29-bit identifier
    bool rtr = false;       // remote transmission request
    bool error = false;     // error frame (id holds the SocketCAN CAN_ERR_* class bits)
    std::uint8_t len = 0;   // 0..8 data bytes
    std::array<std::uint8_t, 8> data{};

    friend bool operator==(const CanFrame&, const CanFrame&) = default;
};

// A frame with the time it was seen or is due (ns; the clock is stated by the producer:
// candump logs use Unix time).
struct StampedCanFrame {
    std::int64_t time_ns = 0;
    CanFrame frame;
};

}  // namespace mirage::nav
