// SPDX-License-Identifier: Apache-2.0
#pragma once
// Thread-safe BusCounters shared by the backends written here (memory, slcan).
#include <atomic>
#include <cstdint>

#include "mirage/can/can_bus.hpp"

namespace mirage::can::detail {

struct AtomicBusCounters {
    std::atomic<std::uint64_t> rx_frames{0}, tx_frames{0}, tx_failed{0}, error_frames{0},
        bus_off{0}, malformed{0}, nacks{0}, rx_overruns{0};

    BusCounters snapshot() const {
        BusCounters c;
        c.rx_frames = rx_frames;
        c.tx_frames = tx_frames;
        c.tx_failed = tx_failed;
        c.error_frames = error_frames;
        c.bus_off = bus_off;
        c.malformed = malformed;
        c.nacks = nacks;
        c.rx_overruns = rx_overruns;
        return c;
    }
    // Counts a delivered frame and says how it is reported.
    RxStatus count_rx(const nav::CanFrame& f) {
        if (!f.error) {
            ++rx_frames;
            return RxStatus::Frame;
        }
        ++error_frames;
        if ((f.id & err::kBusOff) != 0) ++bus_off;
        return RxStatus::ErrorFrame;
    }
};

}  // namespace mirage::can::detail
