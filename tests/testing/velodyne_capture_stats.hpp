// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>

#include "mirage/velodyne/data_packet.hpp"
#include "mirage/velodyne/position_packet.hpp"
#include "mirage/wire/packet.hpp"

namespace mirage::velodyne {

// min / max / mean of a series.
struct Summary {
    std::uint64_t n = 0;
    double min = 0, max = 0, mean = 0;
    void add(double v);
};

// Structural statistics of a Velodyne stream (issue 3 item 5): built the same way from a real
// capture and from Mirage's packetizer so the two can be compared.
struct CaptureStats {
    std::uint64_t data_packets = 0, position_packets = 0, other_packets = 0;
    std::map<std::size_t, std::uint64_t> data_sizes, position_sizes;  // payload bytes → count
    std::map<std::uint8_t, std::uint64_t> factory1, factory2;         // bytes 1204 / 1205
    std::map<std::uint16_t, std::uint64_t> block_flags;
    // Between consecutive blocks of a packet with different azimuths, 0.01° counts.
    Summary azimuth_step_counts;
    std::map<int, std::uint64_t> azimuth_step_histogram;
    int azimuth_step_mode = 0;
    Summary azimuth_step_per_sequence_deg;  // the same divided by the sequences between them
    Summary timestamp_step_us;              // consecutive data packets (mod one hour)
    Summary data_interval_us, position_interval_us;  // arrival (send) times
    double data_rate_hz = 0, position_rate_hz = 0;
    std::uint64_t zero_distance_slots = 0, slots = 0;
    DecodeCounters decode;
    PositionCounters position;
    std::uint64_t position_rmc = 0;  // sentences parsed as $xxRMC
    // Position timestamp − the closest preceding data timestamp, µs (same clock check).
    Summary position_vs_data_us;
    std::optional<Model> model;  // of the first packet that decoded Ok
    std::optional<ReturnMode> mode;

    // Rotation rate implied by the mean azimuth step per sequence (0 without a model).
    double estimated_rpm() const;
    // Multi-line human-readable summary (tests print it).
    std::string describe() const;
};

// Feed packets in arrival order. Data and position packets are told apart by `stream` (map a
// capture's destination port with stream_for_port).
class CaptureStatsBuilder {
  public:
    void add(wire::Stream stream, std::int64_t time_ns, std::span<const std::uint8_t> bytes);
    void add(const wire::PacketView& packet);
    CaptureStats result() const;

  private:
    CaptureStats s_;
    bool have_data_ = false, have_pos_ = false;
    std::int64_t first_data_ns_ = 0, last_data_ns_ = 0, first_pos_ns_ = 0, last_pos_ns_ = 0;
    std::uint32_t last_ts_ = 0;
    DecodedPacket scratch_;
};

// 2368 → Data, 8308 → Position, else Imu (i.e. "other").
wire::Stream stream_for_port(std::uint16_t dst_port);

}  // namespace mirage::velodyne
