// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <functional>
#include <span>

#include "mirage/core/point.hpp"
#include "mirage/core/time.hpp"

namespace mirage::wire {

// Which UDP stream of a sensor a packet belongs to (each has its own destination port).
enum class Stream : std::uint8_t {
    Data,      // Velodyne 2368, Ouster lidar 7502
    Position,  // Velodyne position packet, 8308
    Imu,       // Ouster IMU, 7503
};

// One encoded packet, valid only during the callback. `time` is when the device would put it
// on the wire (sensor clock), which the UDP sink paces against and the pcap sink records.
struct PacketView {
    Stream stream = Stream::Data;
    core::GpsTime time{};
    std::span<const std::uint8_t> bytes;
};
using PacketFn = std::function<void(const PacketView&)>;

// Turns the pipeline's returns (in pulse order) into a vendor's packets. Pulse k of the sensor's
// scan pattern maps to a firing slot of the device, so pulses without returns still occupy their
// slot and encode as the vendor's no-return.
class Packetizer {
  public:
    virtual ~Packetizer() = default;
    // Returns of pulses in increasing pulse order (several per pulse in multi-return modes).
    virtual void add(std::span<const core::PointRecord> points) = 0;
    // Every pulse before `next_pulse` has been delivered: emit all packets that are complete.
    virtual void advance_to(std::uint64_t next_pulse) = 0;
    // Emits the side-stream packets (Velodyne position, Ouster IMU) due at or before `t` that
    // precede the data packet being filled, ahead of its pulses: a real-time caller hands them
    // to a deadline-ordered sender before it renders that packet (docs/live-navigation.md §1).
    // Those due later come with the data packets as usual; the stream is the same either way.
    virtual void emit_side_packets_until(core::GpsTime t) = 0;
    // End of stream: emit what is complete; a partial data packet is dropped (devices only send
    // whole packets).
    virtual void finish() = 0;
};

}  // namespace mirage::wire
