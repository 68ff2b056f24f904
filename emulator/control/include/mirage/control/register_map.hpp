// SPDX-License-Identifier: Apache-2.0
// The rig's Modbus register map (docs/control.md §2): PDU addresses (0-based), input registers
// read-only (FC 04), holding registers read and written (FC 03, 06, 16). Values wider than 16
// bits occupy consecutive registers, most significant word first (ABCD; `mbpoll -B`).
#pragma once
#include <cstddef>
#include <cstdint>

namespace mirage::control {

inline constexpr std::uint16_t kProductId = 0x4D52;  // "MR"
inline constexpr std::size_t kMaxSensors = 16;

// Input registers.
namespace ir {
inline constexpr std::uint16_t kProduct = 0;
inline constexpr std::uint16_t kVersion = 1;  // major, minor, patch
inline constexpr std::uint16_t kRigHash = 4;  // 64-bit FNV-1a of the rig file's bytes
inline constexpr std::uint16_t kState = 8;
inline constexpr std::uint16_t kLastError = 9;
inline constexpr std::uint16_t kScenario = 10;  // the scenario the last arm loaded
inline constexpr std::uint16_t kScenarioCount = 11;
inline constexpr std::uint16_t kSensorCount = 12;
inline constexpr std::uint16_t kWatchdogExpiries = 13;
inline constexpr std::uint16_t kRequests = 14;     // 32-bit: requests answered
inline constexpr std::uint16_t kExceptions = 16;   // 32-bit: of which with an exception
inline constexpr std::uint16_t kRuns = 18;         // starts since the rig was loaded
inline constexpr std::uint16_t kSimTime = 20;      // 64-bit GPS ns of the newest pulse rendered
inline constexpr std::uint16_t kNavRate = 30;      // 32-bit: navigation samples applied, last 1 s
inline constexpr std::uint16_t kNavRejected = 32;  // 32-bit: messages and samples rejected
inline constexpr std::uint16_t kPoseAge = 34;      // 32-bit ms; 0xFFFFFFFF: no pose
inline constexpr std::uint16_t kSensorBase = 100;
inline constexpr std::uint16_t kSensorStride = 20;
// Offsets in a sensor's block.
inline constexpr std::uint16_t kSensorState = 0;  // SensorState
inline constexpr std::uint16_t kPackets = 2;      // 32-bit each from here
inline constexpr std::uint16_t kPoints = 4;
inline constexpr std::uint16_t kLate = 6;
inline constexpr std::uint16_t kSendFailed = 8;
inline constexpr std::uint16_t kStalePeriods = 10;
inline constexpr std::uint16_t kDropped = 12;  // packets dropped by the drop fault
}  // namespace ir

// Holding registers.
namespace hr {
inline constexpr std::uint16_t kCommand = 0;   // write a Command; reads the last accepted one
inline constexpr std::uint16_t kScenario = 1;  // scenario the next arm loads
inline constexpr std::uint16_t kHeartbeat = 2;
inline constexpr std::uint16_t kWatchdogMs = 3;  // 0: off, else 100..60000
inline constexpr std::uint16_t kFaultBase = 100;
inline constexpr std::uint16_t kFaultStride = 10;
// Offsets in a sensor's fault block.
inline constexpr std::uint16_t kDropRate = 0;    // chance a burst starts at a packet, 1/10000
inline constexpr std::uint16_t kDropBurst = 1;   // packets per burst, 1..1000
inline constexpr std::uint16_t kFreezeNav = 2;   // 0/1: the pose of the moment is held
inline constexpr std::uint16_t kRangeBias = 3;   // int16 mm
inline constexpr std::uint16_t kRangeNoise = 4;  // extra σ, mm, 0..10000
inline constexpr std::uint16_t kStaleNav = 5;    // 0/1: as if no navigation arrived
inline constexpr std::uint16_t kStopSensor = 6;  // 0/1: the sensor sends nothing
inline constexpr std::uint16_t kFaultFields = 7;
}  // namespace hr

enum class RigState : std::uint16_t { Idle = 0, Armed = 1, Running = 2, Stopped = 3, Fault = 4 };
enum class Command : std::uint16_t { None = 0, Arm = 1, Start = 2, Stop = 3, Reset = 4 };
enum class SensorState : std::uint16_t { Off = 0, Streaming = 1, Stopped = 2, Failed = 3 };

// Why the last write was refused or the rig faulted (ir::kLastError).
enum class ErrorCode : std::uint16_t {
    None = 0,
    CommandInState = 1,     // the command is not allowed in this state (exception 06)
    ValueOutOfRange = 2,    // exception 03
    NotWritable = 3,        // a write to a register that is not writable (exception 02)
    WatchdogExpired = 4,    // the controller fell silent: safe state (docs/control.md §4)
    SensorFailed = 5,       // a sensor's output failed while running
    NavigationLost = 6,     // no first pose within navigation.first_nav_timeout
    ScenarioWhileBusy = 7,  // scenario written while armed or running (exception 06)
};

// Modbus exception codes (Modbus Application Protocol v1.1b3 §7).
enum class Exception : std::uint8_t {
    None = 0,
    IllegalFunction = 1,
    IllegalAddress = 2,
    IllegalValue = 3,
    ServerFailure = 4,  // the server could not answer (an internal error, counted)
    ServerBusy = 6,
};

inline constexpr std::size_t input_registers(std::size_t sensors) {
    return ir::kSensorBase + ir::kSensorStride * sensors;
}
inline constexpr std::size_t holding_registers(std::size_t sensors) {
    return hr::kFaultBase + hr::kFaultStride * sensors;
}

}  // namespace mirage::control
