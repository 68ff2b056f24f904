// SPDX-License-Identifier: Apache-2.0
#include "mirage/control/control_model.hpp"

#include <gtest/gtest.h>

#include <array>
#include <initializer_list>

namespace mirage::control {
namespace {

constexpr std::int64_t kMs = 1'000'000;

Identity two_sensors() {
    Identity id;
    id.version[0] = 1;
    id.rig_hash = 0x0123456789ABCDEFull;
    id.scenarios = 3;
    id.sensors = 2;
    return id;
}

Request write(std::uint16_t address, std::initializer_list<std::uint16_t> values) {
    Request r;
    r.function = values.size() == 1 ? Function::WriteSingle : Function::WriteMultiple;
    r.address = address;
    for (auto v : values) r.values[r.count++] = v;
    return r;
}

std::uint16_t read1(ControlModel& m, Function f, std::uint16_t address) {
    Request r;
    r.function = f;
    r.address = address;
    r.count = 1;
    std::array<std::uint16_t, 1> out{};
    EXPECT_EQ(m.handle(r, 0, out), Exception::None);
    return out[0];
}

Exception cmd(ControlModel& m, Command c, std::int64_t now = 0) {
    std::array<std::uint16_t, 0> none{};
    return m.handle(write(hr::kCommand, {static_cast<std::uint16_t>(c)}), now, none);
}

TEST(ControlModel, ArmStartStopResetAndStartOnlyWhenArmed) {
    ControlModel m(two_sensors(), {}, 0);
    EXPECT_EQ(cmd(m, Command::Start), Exception::ServerBusy);
    EXPECT_EQ(m.last_error(), ErrorCode::CommandInState);
    EXPECT_EQ(m.state(), RigState::Idle);
    EXPECT_EQ(cmd(m, Command::Stop), Exception::ServerBusy);
    EXPECT_EQ(cmd(m, Command::Arm), Exception::None);
    EXPECT_EQ(m.state(), RigState::Armed);
    EXPECT_EQ(cmd(m, Command::Start), Exception::None);
    EXPECT_EQ(m.state(), RigState::Running);
    EXPECT_EQ(m.runs(), 1u);
    EXPECT_EQ(cmd(m, Command::Arm), Exception::ServerBusy);
    EXPECT_EQ(cmd(m, Command::Stop), Exception::None);
    EXPECT_EQ(m.state(), RigState::Stopped);
    EXPECT_EQ(cmd(m, Command::Start), Exception::ServerBusy);  // arm again first
    EXPECT_EQ(cmd(m, Command::Reset), Exception::None);
    EXPECT_EQ(m.state(), RigState::Idle);
    EXPECT_EQ(m.last_error(), ErrorCode::None);
    EXPECT_EQ(read1(m, Function::ReadHolding, hr::kCommand), 4);
}

// A run that finishes or fails after the controller stopped it and started the next one leaves
// the next one running.
TEST(ControlModel, AnOldRunsEndDoesNotEndTheNextRun) {
    ControlModel m(two_sensors(), {}, 0);
    cmd(m, Command::Arm);
    cmd(m, Command::Start);
    const std::uint64_t first = m.order().run;
    EXPECT_EQ(first, 1u);
    cmd(m, Command::Stop);
    cmd(m, Command::Arm);
    cmd(m, Command::Start);  // while run 1 still shuts down
    EXPECT_EQ(m.order().run, 2u);
    m.run_ended(first);
    m.fault(first, ErrorCode::SensorFailed);
    EXPECT_EQ(m.state(), RigState::Running);
    EXPECT_EQ(m.last_error(), ErrorCode::None);
    m.fault(2, ErrorCode::SensorFailed);  // the current run's failure counts
    EXPECT_EQ(m.state(), RigState::Fault);
    EXPECT_EQ(m.last_error(), ErrorCode::SensorFailed);
    m.run_ended(2);  // and nothing leaves fault but reset
    EXPECT_EQ(m.state(), RigState::Fault);
}

TEST(ControlModel, AWriteIsAppliedWholeOrNotAtAll) {
    ControlModel m(two_sensors(), {}, 0);
    std::array<std::uint16_t, 0> none{};
    const std::uint16_t f1 = hr::kFaultBase + hr::kFaultStride;  // sensor 1's block
    // Drop rate 500, burst 0 (out of range): neither lands.
    EXPECT_EQ(m.handle(write(f1, {500, 0}), 0, none), Exception::IllegalValue);
    EXPECT_EQ(m.last_error(), ErrorCode::ValueOutOfRange);
    EXPECT_EQ(m.faults(1).load(), FaultSettings{});
    // Into the reserved fields 7..9: address refused before any value is looked at.
    EXPECT_EQ(m.handle(write(f1 + 5, {1, 0, 0}), 0, none), Exception::IllegalAddress);
    EXPECT_FALSE(m.faults(1).load().stale_nav);
    EXPECT_EQ(m.handle(write(hr::kWatchdogMs + 1, {1}), 0, none), Exception::IllegalAddress);
    // A whole block at once: every field lands in the sensor's cell.
    EXPECT_EQ(m.handle(write(f1, {500, 4, 0, 0xFF38, 30, 1, 1}), 0, none), Exception::None);
    const FaultSettings f = m.faults(1).load();
    EXPECT_EQ(f.drop_rate, 500);
    EXPECT_EQ(f.drop_burst, 4);
    EXPECT_EQ(f.range_bias_mm, -200);
    EXPECT_EQ(f.range_noise_mm, 30);
    EXPECT_TRUE(f.stale_nav && f.stop && !f.freeze_nav);
    EXPECT_EQ(m.faults(0).load(), FaultSettings{});
    EXPECT_EQ(read1(m, Function::ReadHolding, f1 + hr::kRangeBias), 0xFF38);
    // Reset restores the rig file's defaults.
    EXPECT_EQ(cmd(m, Command::Reset), Exception::None);
    EXPECT_EQ(m.faults(1).load(), FaultSettings{});
}

TEST(ControlModel, ScenarioIsSelectedBeforeTheArmInOneRequest) {
    ControlModel m(two_sensors(), {}, 0);
    std::array<std::uint16_t, 0> none{};
    EXPECT_EQ(m.handle(write(hr::kScenario, {3}), 0, none), Exception::IllegalValue);
    // Command and scenario in one write: the scenario lands first, the arm loads it.
    EXPECT_EQ(m.handle(write(hr::kCommand, {1, 2}), 0, none), Exception::None);
    EXPECT_EQ(m.order().scenario, 2);
    EXPECT_EQ(read1(m, Function::ReadInput, ir::kScenario), 2);
    EXPECT_EQ(m.handle(write(hr::kScenario, {1}), 0, none), Exception::ServerBusy);
    EXPECT_EQ(m.last_error(), ErrorCode::ScenarioWhileBusy);
    EXPECT_EQ(read1(m, Function::ReadHolding, hr::kScenario), 2);
}

TEST(ControlModel, WatchdogFaultsARunningRigWhenHeartbeatsStop) {
    ControlModel m(two_sensors(), {}, 500);
    std::array<std::uint16_t, 0> none{};
    m.tick(10'000 * kMs);  // idle: the watchdog does not run
    EXPECT_EQ(m.state(), RigState::Idle);
    EXPECT_EQ(cmd(m, Command::Arm, 0), Exception::None);
    EXPECT_EQ(cmd(m, Command::Start, 100 * kMs), Exception::None);
    EXPECT_EQ(m.handle(write(hr::kHeartbeat, {7}), 550 * kMs, none), Exception::None);
    m.tick(1000 * kMs);
    EXPECT_EQ(m.state(), RigState::Running);
    m.tick(1051 * kMs);
    EXPECT_EQ(m.state(), RigState::Fault);
    EXPECT_EQ(m.last_error(), ErrorCode::WatchdogExpired);
    EXPECT_EQ(read1(m, Function::ReadInput, ir::kWatchdogExpiries), 1);
    EXPECT_EQ(cmd(m, Command::Arm), Exception::ServerBusy);  // only reset leaves the fault
    EXPECT_EQ(cmd(m, Command::Reset), Exception::None);
    EXPECT_EQ(m.state(), RigState::Idle);
    EXPECT_EQ(m.handle(write(hr::kWatchdogMs, {99}), 0, none), Exception::IllegalValue);
    EXPECT_EQ(m.handle(write(hr::kWatchdogMs, {0}), 0, none), Exception::None);
}

TEST(ControlModel, InputRegistersCarryWordsMostSignificantFirst) {
    ControlModel m(two_sensors(), {}, 0);
    RigStatus s;
    s.sim_time_ns = 0x0011223344556677;
    s.pose_age_ms.reset();
    s.sensors.resize(2);
    s.sensors[1].packets = 0x12345678;
    s.sensors[1].late = 0x1'0000'0000;  // saturates at 2³²-1
    s.sensors[1].state = SensorState::Streaming;
    m.set_status(s);
    const auto in = [&](std::uint16_t a) { return read1(m, Function::ReadInput, a); };
    EXPECT_EQ(in(ir::kProduct), kProductId);
    EXPECT_EQ(in(ir::kRigHash), 0x0123);
    EXPECT_EQ(in(ir::kRigHash + 3), 0xCDEF);
    EXPECT_EQ(in(ir::kSimTime), 0x0011);
    EXPECT_EQ(in(ir::kSimTime + 3), 0x6677);
    EXPECT_EQ(in(ir::kPoseAge), 0xFFFF);
    const std::uint16_t b = ir::kSensorBase + ir::kSensorStride;
    EXPECT_EQ(in(b + ir::kSensorState), 1);
    EXPECT_EQ(in(b + ir::kPackets), 0x1234);
    EXPECT_EQ(in(b + ir::kPackets + 1), 0x5678);
    EXPECT_EQ(in(b + ir::kLate), 0xFFFF);
    EXPECT_EQ(in(b + ir::kLate + 1), 0xFFFF);
    EXPECT_EQ(in(ir::kSensorCount), 2);
    EXPECT_EQ(in(ir::kScenarioCount), 3);
    EXPECT_GE(in(ir::kRequests + 1), 12);  // the reads above
}

TEST(ControlModel, FreezeIsRefusedWhereThereIsNoNavigationStream) {
    Identity id = two_sensors();
    id.can_freeze_nav = false;
    ControlModel m(id, {}, 0);
    std::array<std::uint16_t, 0> none{};
    EXPECT_EQ(m.handle(write(hr::kFaultBase + hr::kFreezeNav, {1}), 0, none),
              Exception::IllegalValue);
    EXPECT_EQ(m.handle(write(hr::kFaultBase + hr::kFreezeNav, {0}), 0, none), Exception::None);
}

TEST(ControlModel, DefaultFaultsFromTheRigFileApplyAtLoad) {
    FaultSettings d;
    d.range_bias_mm = 50;
    ControlModel m(two_sensors(), {FaultSettings{}, d}, 0);
    EXPECT_EQ(m.faults(1).load().range_bias_mm, 50);
    EXPECT_EQ(read1(m, Function::ReadHolding, hr::kFaultBase + hr::kFaultStride + 3), 50);
}

}  // namespace
}  // namespace mirage::control
