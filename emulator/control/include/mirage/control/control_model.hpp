// SPDX-License-Identifier: Apache-2.0
// The rig's control state (docs/control.md §2-4): the state machine (idle, armed, running,
// stopped, fault), the holding registers a controller writes, the input registers it reads, the
// heartbeat watchdog. A write is checked whole — addresses, then values, then the state — and
// applied whole or not at all. Thread-safe: the control thread answers requests, the rig's
// supervisor polls the state and reports run ends; sensor threads only load their FaultCell.
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "mirage/control/register_map.hpp"
#include "mirage/control/request.hpp"
#include "mirage/control/sensor_faults.hpp"

namespace mirage::control {

struct Identity {
    std::uint16_t version[3] = {0, 0, 0};
    std::uint64_t rig_hash = 0;
    std::uint16_t scenarios = 1;
    std::size_t sensors = 0;
    bool can_freeze_nav = true;  // a trajectory rig has no navigation stream to freeze
};

struct SensorStatus {
    SensorState state = SensorState::Off;
    std::uint64_t packets = 0, points = 0, late = 0, send_failed = 0, stale_periods = 0,
                  dropped = 0;
};

// What the rig measured, refreshed before input registers are read.
struct RigStatus {
    std::int64_t sim_time_ns = 0;
    std::uint64_t nav_rate = 0, nav_rejected = 0;
    std::optional<std::int64_t> pose_age_ms;
    std::vector<SensorStatus> sensors;
};

class ControlModel {
  public:
    // `defaults`: the rig file's faults per sensor (applied at load and at reset).
    ControlModel(Identity id, std::vector<FaultSettings> defaults, std::uint16_t watchdog_ms);

    std::size_t input_window() const { return input_registers(id_.sensors); }
    std::size_t holding_window() const { return holding_registers(id_.sensors); }

    // Answers a checked request at host time `now_ns`; reads fill `out` (request.count values).
    Exception handle(const Request& r, std::int64_t now_ns, std::span<std::uint16_t> out);
    // A request refused before the model saw it (malformed): counted as an exception.
    void count_refused();
    void set_status(RigStatus s);

    // The rig's side. Each start is a new run, numbered from 1; a run's end or failure applies
    // only while that run is still the one running, so a stop-arm-start issued while the previous
    // run shuts down is not undone when it finishes.
    struct Order {
        RigState state = RigState::Idle;
        std::uint64_t run = 0;       // the latest start
        std::uint16_t scenario = 0;  // the one the last arm loaded
    };
    Order order() const;
    RigState state() const;
    // The watchdog: in armed or running, no heartbeat for the timeout -> fault (safe state).
    void tick(std::int64_t now_ns);
    void run_ended(std::uint64_t run);                // running -> stopped (duration over)
    void fault(std::uint64_t run, ErrorCode reason);  // running -> fault
    const FaultCell& faults(std::size_t sensor) const { return *cells_[sensor]; }
    ErrorCode last_error() const;
    std::uint64_t runs() const;

  private:
    std::pair<Exception, ErrorCode> check_write(const Request& r) const;
    std::uint16_t holding(std::uint16_t a) const;
    std::uint16_t input(std::uint16_t a) const;
    Exception refuse(Exception e, ErrorCode why);
    void apply(std::uint16_t address, std::uint16_t value, std::int64_t now_ns);
    void command(Command c, std::int64_t now_ns);

    mutable std::mutex m_;
    Identity id_;
    std::vector<FaultSettings> defaults_, faults_;
    std::vector<std::unique_ptr<FaultCell>> cells_;
    RigState state_ = RigState::Idle;
    ErrorCode last_error_ = ErrorCode::None;
    Command last_command_ = Command::None;
    std::uint16_t selected_ = 0, loaded_ = 0, heartbeat_ = 0, watchdog_ms_ = 0;
    std::int64_t heartbeat_ns_ = 0;
    std::uint64_t requests_ = 0, exceptions_ = 0, expiries_ = 0, runs_ = 0;
    RigStatus status_;
};

}  // namespace mirage::control
