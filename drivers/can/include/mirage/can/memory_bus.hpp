// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>
#include <string>

#include "mirage/can/can_bus.hpp"

namespace mirage::can {

// An in-process bus: every bus opened with the same `name` receives the frames the others
// send (not its own), in send order. Thread-safe; receive() waits on a condition variable up
// to its deadline. `host_ns` is the CLOCK_MONOTONIC time the frame was put on the bus. Each
// receiver queues at most kMemoryBusQueue frames; beyond that new frames are dropped for it
// and counted in its rx_overruns. A frame with `error` set is delivered as an ErrorFrame (how
// tests inject bus errors and bus-off). The name lives while one bus with it is open.
inline constexpr std::size_t kMemoryBusQueue = 65'536;
std::unique_ptr<CanBus> open_memory_bus(const std::string& name);

}  // namespace mirage::can
