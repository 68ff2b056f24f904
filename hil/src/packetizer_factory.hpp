// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <memory>
#include <string>

#include "job.hpp"
#include "mirage/wire/packet.hpp"

namespace mirage::hil {

struct WireOptions {
    std::string return_mode = "strongest";  // Velodyne: strongest | last | dual
    std::string profile = "LEGACY";  // Ouster: LEGACY | RNG19_RFL8_SIG16_NIR16 | RNG15_RFL8_NIR8
    bool position_packets = true;    // Velodyne position stream (off when its port is 0)
    bool imu_packets = true;         // Ouster IMU stream (off when its port is 0)
};

// Ouster presets are named os<P>-<H>-<W>x<F>.
inline bool is_ouster(const std::string& sensor_name) { return sensor_name.rfind("os", 0) == 0; }

// Pipeline points into a packetizer; pulses without returns still advance it.
class PacketizerSink : public render::PointSink {
  public:
    explicit PacketizerSink(wire::Packetizer& p) : p_(p) {}
    void write(std::span<const core::PointRecord> points) override { p_.add(points); }
    void pulses_done(std::uint64_t next_pulse) override { p_.advance_to(next_pulse); }

  private:
    wire::Packetizer& p_;
};

// A sensor's packet encoder and the side files its clients need.
struct WireSetup {
    std::unique_ptr<wire::Packetizer> packetizer;
    std::string vendor;             // "velodyne" | "ouster"
    std::string side_file;          // calibration YAML (Velodyne) or metadata JSON (Ouster)
    std::string side_file_kind;     // "calibration" | "metadata"
    std::string side_file_ext;      // ".yaml" | ".json"
    double packets_per_second = 0;  // data packets, from the model's closed form
};

// Velodyne presets (vlp16, vlp16-hires, vlp32c, hdl32e, hdl64e-s3) or Ouster presets
// (os<P>-<H>-<W>x<F>). Throws ConfigError for other sensors or options the model lacks. The job's
// sensor must already carry the rpm and return count the packets need (see prepare_sensor).
WireSetup make_wire(const Job& job, const WireOptions& options, wire::PacketFn sink,
                    const std::string& udp_host);

// Applies --rpm and the returns a return mode needs to the job's sensor, before rendering.
// Throws ConfigError for a sensor without a wire format or an rpm the family does not allow.
void prepare_sensor(Job& job, const WireOptions& options, double rpm);

}  // namespace mirage::hil
