// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "mirage/ouster/descriptor.hpp"
#include "mirage/ouster/imu.hpp"
#include "mirage/ouster/lidar_packet.hpp"

namespace mirage::ouster {

struct DecodeCounters {
    std::array<std::uint64_t, kDecodeStatusCount> by_status{};  // indexed by DecodeStatus
    std::uint64_t packets = 0;                                  // lidar packets offered
    std::uint64_t crc_valid = 0;            // non-legacy footers holding a matching CRC-64
    std::uint64_t crc_placeholder = 0;      // FW 2.x footers
    std::uint64_t dropped_columns = 0;      // status bit 0 clear
    std::uint64_t measurement_id_gaps = 0;  // places where columns went missing
    std::uint64_t missing_columns = 0;      // columns never received
    std::uint64_t frames = 0;               // frame IDs started
    std::uint64_t imu_packets = 0;
    std::uint64_t imu_wrong_size = 0;
    std::uint64_t errors() const;  // lidar packets with a status other than Ok, + bad IMU sizes
};

// Sensor: Ouster's sensor frame (what ouster-sdk returns; lidar_to_sensor applied). Lidar:
// Ouster's lidar frame, which is Mirage's sensor frame for the Ouster presets (FLU, column 0
// along +x, azimuth clockwise).
enum class PointFrame : std::uint8_t { Sensor, Lidar };

struct OusterPoint {
    double x = 0, y = 0, z = 0;  // m
    std::uint64_t timestamp_ns = 0;
    std::uint32_t range_mm = 0;
    std::uint16_t row = 0, measurement_id = 0, frame_id = 0;
    std::uint16_t reflectivity = 0, signal = 0, nir = 0;
};

// Stateful decoder of one sensor's streams: status counts, measurement-ID gap tracking across
// packets (a dropped packet shows as a gap; a new frame ID must continue where the last ended),
// and XYZ per docs/wire-formats.md §2.8. Never throws after construction.
class Decoder {
  public:
    explicit Decoder(Descriptor d);

    DecodeStatus decode(std::span<const std::uint8_t> bytes);
    // The last decoded packet (valid after decode() returned Ok).
    const LidarPacket& packet() const { return packet_; }
    bool decode_imu(std::span<const std::uint8_t> bytes, ImuPacket& out);

    // Appends the returns (range > 0) of the valid columns of the last Ok packet.
    void points(PointFrame frame, std::vector<OusterPoint>& out) const;
    // §2.8 for one pixel, metres.
    Eigen::Vector3d xyz(std::size_t row, std::uint16_t measurement_id, std::uint32_t range_mm,
                        PointFrame frame) const;

    const DecodeCounters& counters() const { return counters_; }
    const Descriptor& descriptor() const { return d_; }

  private:
    Descriptor d_;
    LidarPacket packet_;
    DecodeCounters counters_;
    struct RowTrig {
        double cos_az, sin_az, cos_alt, sin_alt;
    };
    std::vector<RowTrig> rows_;
    Eigen::Matrix3d sensor_r_lidar_;
    Eigen::Vector3d sensor_t_lidar_mm_;
    bool have_last_ = false;
    std::uint16_t last_frame_ = 0;
    std::uint32_t next_mid_ = 0;  // expected measurement ID of the next column
    bool last_ok_ = false;
};

}  // namespace mirage::ouster
