// SPDX-License-Identifier: Apache-2.0
// A rig file made ready to run (docs/rig.md §2): one scene and BVH, one trajectory and start time,
// and per sensor its job (mount applied), wire settings, ports and packet rate. Errors name the
// rig file, the sensor's key path and line.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "job.hpp"
#include "mirage/rig/rig_config.hpp"
#include "mirage/udp/udp_sender.hpp"
#include "mirage/wire/setup.hpp"

namespace mirage::hil {

struct RigSensor {
    rig::SensorEntry entry;
    Job job;
    wire::WireOptions wire;
    udp::StreamPorts ports;
    std::string vendor;
    double packets_per_second = 0;
};

struct RigPlan {
    rig::RigConfig config;
    bool forever = false;             // a static pose without a duration: until Ctrl-C
    bool start_now = false;           // first pulse "now": on the host's clock (docs/time.md)
    std::string live_duration;        // a live source: seconds to run (empty: until Ctrl-C)
    core::Nanos live_duration_ns{0};  // the same, parsed (0: until Ctrl-C)
    std::vector<std::unique_ptr<RigSensor>> sensors;
};

// `duration_override`: --duration when given. Opens no socket or file. `reuse`: a plan of the
// same rig file whose scene and BVH this one shares instead of loading and building its own (a
// controlled rig plans each scenario at load and again at each start).
RigPlan plan_rig(const rig::RigConfig& config, const std::string& duration_override,
                 const RigPlan* reuse = nullptr);
// The effective configuration, one block per sensor (`mirage rig --check`).
std::string describe(const RigPlan& plan);

}  // namespace mirage::hil
