// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "mirage/ouster/descriptor.hpp"
#include "mirage/ouster/imu.hpp"
#include "mirage/ouster/lidar_packet.hpp"
#include "mirage/ouster/sensor_clock.hpp"
#include "mirage/wire/packet.hpp"

namespace mirage::ouster {

struct PacketizerConfig {
    core::GpsTime start{};  // firing time of pulse 0 (render::RenderOptions::start)
    std::uint16_t first_frame_id = 0;
    SensorClock clock;
    // IMU stream (port 7503) at `imu_period` from `start`; none when empty. Typically
    // [&](GpsTime t) { return imu_reading(trajectory, mount, descriptor, t); }.
    std::function<ImuReading(core::GpsTime)> imu;
    core::Nanos imu_period{std::chrono::milliseconds(10)};  // 100 Hz (§2.1)
    // Accelerometer / gyro read times after the system timestamp (the OS-2 capture of §6 shows
    // 214.55 µs / 437.32 µs); the reading itself is taken at the system time.
    core::Nanos imu_accel_delay{0};
    core::Nanos imu_gyro_delay{0};
    std::uint16_t nir = 0;  // ambient (no ambient model yet)
};

struct PacketizerStats {
    std::uint64_t lidar_packets = 0;
    std::uint64_t imu_packets = 0;
    std::uint64_t returns = 0;        // pixels written with a range
    std::uint64_t out_of_range = 0;   // returns beyond the profile's range field → no return
    std::uint64_t extra_returns = 0;  // weaker returns of a pulse (single-return profiles)
    std::uint64_t out_of_order = 0;   // points of an already emitted packet (ignored)
};

// Pulse k of the preset's SpinningPattern (all beams of a column fire together, so slot = beam):
// column s = k / H (global), beam = k % H = PointRecord::channel; measurement ID = s mod W; frame
// ID = first_frame_id + s / W (mod 2¹⁶); column time = start + round(s·1e9/(W·F)) ns (the
// pattern's rounding), stamped through `clock`; encoder count = mid·90112/W. A lidar packet is
// emitted, stamped at the end of its last column, once all its pulses are delivered; IMU packets
// in time order between them. Range written: R + n·(1 − cos φ·cos θa) (n = beam origin offset),
// the least-squares value for which the SDK formula of §2.8 returns the renderer's hit (the
// renderer casts from the lidar origin; residual ≤ n·sin of the beam's angle to the column plane,
// ≈ 5 mm for the OS1-128's top beam). Reflectivity = intensity >> 8, signal = photo-electrons.
class OusterPacketizer final : public wire::Packetizer {
  public:
    OusterPacketizer(Descriptor d, PacketizerConfig cfg, wire::PacketFn sink);

    void add(std::span<const core::PointRecord> points) override;
    void advance_to(std::uint64_t next_pulse) override;
    void emit_side_packets_until(core::GpsTime t) override;
    void finish() override;

    const PacketizerStats& stats() const { return stats_; }
    const Descriptor& descriptor() const { return d_; }
    // Closed forms used by the packetizer (and by tests).
    core::GpsTime column_time(std::uint64_t column) const;
    std::uint16_t measurement_id(std::uint64_t column) const;
    std::uint16_t frame_id(std::uint64_t column) const;

  private:
    void emit_through(std::uint64_t packet_end);  // emit packets [current_, packet_end)
    void emit_current();
    void emit_imu_until(core::GpsTime t);
    void reset_buffer();

    Descriptor d_;
    PacketizerConfig cfg_;
    wire::PacketFn sink_;
    std::uint64_t pulses_per_packet_;
    std::uint64_t current_ = 0;  // packet being filled
    LidarPacket packet_;
    std::vector<double> best_;          // photo-electrons of the kept return per pixel (−1: none)
    std::vector<double> range_add_mm_;  // per-row range correction
    std::vector<std::uint8_t> bytes_;
    std::uint64_t next_imu_ = 0;  // index of the next IMU packet
    core::GpsTime covered_{};     // every pulse before this time has been delivered
    PacketizerStats stats_;
};

}  // namespace mirage::ouster
