// SPDX-License-Identifier: Apache-2.0
// Running a planned rig once (docs/rig.md §2): every sensor rendered and paced in one process on
// one sensor clock, from a trajectory or from one live navigation source; each sensor's faults
// (docs/control.md §5) applied on its way to the wire. A RigView lets the control plane read the
// running sensors' counters without ever blocking them.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "live_loop.hpp"
#include "mirage/control/control_model.hpp"
#include "mirage/control/sensor_faults.hpp"
#include "mirage/hostclock/keep_awake.hpp"
#include "mirage/las/las_writer.hpp"
#include "mirage/output/packet_output.hpp"
#include "rig_plan.hpp"

namespace mirage::hil {

// One sensor of the running rig: its output, encoder, faults and what its thread measured.
struct RigRun {
    RigSensor* sensor = nullptr;
    std::unique_ptr<output::PacketOutput> out;
    wire::WireSetup wire;
    const control::FaultCell* cell = nullptr;
    control::FaultCell own_cell;  // the rig file's faults when no control plane holds them
    std::unique_ptr<control::PacketDropper> dropper;
    std::unique_ptr<las::LasWriter> las;               // the sensor's `las` file, if any
    std::unique_ptr<wire::Packetizer> las_tee;         // writes it, in front of faulty
    std::unique_ptr<control::FaultPacketizer> faulty;  // in front of wire.packetizer
    wire::Packetizer* input = nullptr;                 // where the renderer's points go
    std::atomic<std::uint64_t> packets{0}, dropped{0}, withheld{0};
    std::atomic<std::int64_t> newest_ns{0};  // sensor time of the newest packet
    std::atomic<bool> running{false}, failed{false};
    std::atomic<bool> quiet{false};  // stopped: its queue was dropped at the first withheld packet
    // Under a control plane: the run's stop flag; once set, nothing more is handed to the sender
    // and what it holds is dropped (a stopped or faulted rig goes quiet at once).
    const std::atomic<bool>* halt = nullptr;
    std::unique_ptr<LiveSession> session;           // live navigation: sends through the session
    hostclock::ClockStepFollower* clock = nullptr;  // on the host's clock: its steps
    render::RenderStats stats;
    LiveTotals live;
    output::PacketOutputTotals totals;
    std::string error;
};

// What the control plane reads: the runs of the rig while it runs (none otherwise).
class RigView {
  public:
    void publish(std::vector<std::unique_ptr<RigRun>>* runs, const navio::NavInput* nav,
                 const navpose::PoseBuffer* poses);
    void clear() { publish(nullptr, nullptr, nullptr); }
    control::RigStatus status() const;
    bool sensor_failed() const;  // a sensor of the published run has failed

  private:
    mutable std::mutex m_;
    std::vector<std::unique_ptr<RigRun>>* runs_ = nullptr;
    const navio::NavInput* nav_ = nullptr;
    const navpose::PoseBuffer* poses_ = nullptr;
    mutable std::int64_t rate_at_ns_ = 0;
    mutable std::uint64_t applied_at_ = 0, rate_ = 0;
};

struct RigRunOptions {
    bool status_line = true;
    int rt_priority = 0;
    const std::atomic<bool>* stop = nullptr;         // required
    const control::ControlModel* control = nullptr;  // per-sensor faults; null: the rig file's
    RigView* view = nullptr;
    // --keep-awake: the sender runs on the CPU it keeps awake, and its spinner's CPU time is not
    // the rig's (docs/time.md §5).
    const hostclock::KeepAwake* awake = nullptr;
    // Set by run_rig for a rig on the host's clock: one follower of its steps for every sensor.
    hostclock::ClockStepFollower* clock = nullptr;
};

// The faults of the rig file in the control plane's units, one per sensor.
std::vector<control::FaultSettings> rig_fault_defaults(const rig::RigConfig& config);

// Runs every sensor until the duration is over or `stop`; prints the summary. Throws IoError
// naming the first sensor that failed.
void run_rig(RigPlan& plan, const RigRunOptions& o);
void run_rig_live(RigPlan& plan, const RigRunOptions& o);

}  // namespace mirage::hil
