// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>
#include <string>

#include "mirage/can/can_bus.hpp"

namespace mirage::can {

// A raw AF_CAN socket bound to `ifname`, with error frames enabled. Throws IoError
// ("socketcan 'can0': ...") when the kernel has no AF_CAN or the interface does not exist.
std::unique_ptr<CanBus> open_socketcan(const std::string& ifname);

}  // namespace mirage::can
