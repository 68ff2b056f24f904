// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

#include "mirage/ouster/decoder.hpp"

namespace mirage::ouster {

// One datagram with the time it was put on / taken off the wire (any ns epoch).
struct TimedPacket {
    std::int64_t time_ns = 0;
    std::span<const std::uint8_t> bytes;
};

// The structure of an Ouster stream, comparable between a real capture and our packetizer
// (issue 3 item 5). Medians make it robust to the capture host's jitter.
struct CaptureStats {
    std::uint64_t lidar_packets = 0;
    std::size_t lidar_packet_bytes = 0;  // most common size
    std::uint64_t decode_errors = 0;     // lidar packets not Ok + IMU packets of a wrong size
    std::uint64_t crc_valid = 0, crc_placeholder = 0;
    std::uint64_t measurement_id_gaps = 0;
    std::uint32_t columns_per_packet = 0;
    double column_ts_step_ns = 0;          // median step between adjacent columns' timestamps
    std::int64_t measurement_id_step = 0;  // most common step between adjacent columns
    std::int64_t encoder_step = 0;         // most common step of the LEGACY encoder count (0: none)
    std::uint32_t packets_per_frame = 0;   // most packets seen with one frame ID
    double lidar_packet_interval_ns = 0;   // median interval between lidar packets
    std::uint64_t imu_packets = 0;
    std::size_t imu_packet_bytes = 0;  // most common size
    double imu_interval_ns = 0;        // median interval of the wire times
    double imu_ts_step_ns = 0;         // median step of the IMU system timestamps
};

// Decodes every packet with `d` (lidar and IMU streams already separated by port).
CaptureStats capture_stats(const Descriptor& d, std::span<const TimedPacket> lidar,
                           std::span<const TimedPacket> imu);

}  // namespace mirage::ouster
