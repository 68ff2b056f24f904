// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "mirage/core/pose.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/scene/scene.hpp"
#include "mirage/sensor/sensor.hpp"
#include "mirage/wire/packet.hpp"

namespace mirage::wire {

// A sensor model bound to its vendor's packet format: the packetizer `mirage emulate` and
// `mirage live` feed, and the side file its clients read. Pure: bytes in memory only.

struct WireOptions {
    std::string return_mode = "strongest";  // Velodyne: strongest | last | dual
    std::string profile = "LEGACY";  // Ouster: LEGACY | RNG19_RFL8_SIG16_NIR16 | RNG15_RFL8_NIR8
    bool position_packets = true;    // Velodyne position stream (off when its port is 0)
    bool imu_packets = true;         // Ouster IMU stream (off when its port is 0)
    // Ouster config_params.timestamp_mode: TIME_FROM_INTERNAL_OSC (ns counted from the GPS
    // epoch), TIME_FROM_SYNC_PULSE_IN (UTC ns since 1970) or TIME_FROM_PTP_1588 (TAI ns since
    // 1970), as the device stamps columns and IMU readings (docs/time.md §3).
    std::string timestamp_mode = "TIME_FROM_INTERNAL_OSC";
};

// What the packets describe besides the returns: the sensor's path (Velodyne $GPRMC through the
// scene's georeference, Ouster IMU readings) and the time of pulse 0. All must outlive the
// packetizer.
struct WireContext {
    const sensor::SensorModel& sensor;
    const scene::Scene& scene;
    const core::Trajectory& trajectory;
    core::Mount mount;
    core::GpsTime start{};
    // The sensor clock is disciplined by GPS (a fix and its PPS, or a trajectory's GPS time).
    // False before an INS's first fix: Velodyne position packets then report PPS absent and a
    // void $GPRMC, as a unit before lock (docs/wire-formats.md §1.9).
    bool gps_locked = true;
    // When set: ns the sensor clock's time source has stepped since the start (a host clock step
    // followed by hostclock::ClockStepFollower), added to the timestamps (docs/time.md §1).
    const std::atomic<std::int64_t>* clock_step = nullptr;
};

// A sensor's packet encoder and the side files its clients need.
struct WireSetup {
    std::unique_ptr<Packetizer> packetizer;
    std::string vendor;             // "velodyne" | "ouster"
    std::string side_file;          // calibration YAML (Velodyne) or metadata JSON (Ouster)
    std::string side_file_kind;     // "calibration" | "metadata"
    std::string side_file_ext;      // ".yaml" | ".json"
    double packets_per_second = 0;  // data packets, from the model's closed form
};

// The packetizer of the sensor's wire family (SensorModel::wire). Throws ConfigError for a sensor
// without one or options its family lacks. The sensor must already carry the rpm and return count
// the packets need (prepare_sensor).
WireSetup make_wire(const WireContext& ctx, const WireOptions& options, PacketFn sink,
                    const std::string& udp_host);

// Applies --rpm and the returns a return mode needs to the sensor, before rendering. Throws
// ConfigError for a sensor without a wire format or an rpm the family does not allow.
void prepare_sensor(sensor::SensorModel& sensor, const WireOptions& options, double rpm);

}  // namespace mirage::wire
