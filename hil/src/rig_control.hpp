// SPDX-License-Identifier: Apache-2.0
// `mirage rig` under a Modbus control plane (docs/control.md): the server answers on its own
// threads; this supervisor enacts the state the controller set — a start runs the selected
// scenario, a stop, a reset or the watchdog's safe state ends the run — and reports how runs end.
#pragma once
#include <string>

#include "mirage/hostclock/keep_awake.hpp"
#include "mirage/rig/rig_config.hpp"

namespace mirage::hil {

struct RigControlOptions {
    std::string duration_override;  // --duration
    bool status_line = true;
    int rt_priority = 0;
    const hostclock::KeepAwake* awake = nullptr;  // --keep-awake (RigRunOptions::awake)
};

// Serves until SIGINT or SIGTERM. Throws IoError when the control address cannot be bound.
void run_controlled_rig(const rig::RigConfig& config, const RigControlOptions& o);

}  // namespace mirage::hil
