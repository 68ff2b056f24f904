// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "mirage/sensor/sensor.hpp"
#include "mirage/velodyne/data_packet.hpp"
#include "mirage/velodyne/model.hpp"
#include "mirage/velodyne/position_packet.hpp"
#include "mirage/wire/packet.hpp"

namespace mirage::velodyne {

// Geodetic position of the sensor at a time, for the $GPRMC of position packets.
using PositionFn = std::function<GeoFix(core::GpsTime)>;

struct PacketizerOptions {
    ReturnMode mode = ReturnMode::Strongest;
    double rpm = 600;
    core::GpsTime start{};  // firing time of pulse 0 (= first firing of sequence 0)
    // Returns beyond this (or beyond the 16-bit distance field) encode as no-return.
    double max_range_m = std::numeric_limits<double>::infinity();
    // Byte 1205; defaults to the model's id (§1.3: configurable apart from the geometry).
    std::optional<std::uint8_t> product_id;
    bool position_packets = true;  // only for models that have them
    GeoFix fixed_position{};       // used when `position` is empty
    PositionFn position;
    PositionPacketOptions position_options{};
    std::uint8_t hdl64_temperature_c = 40;
    std::uint8_t hdl64_gps_status = 'A';  // 'A' PPS + NMEA, 'V', 'P', 0
    // When set: ns the clock source has stepped since the start, added to every timestamp
    // (data, position, $GPRMC, HDL-64E status) from the next packet on; the firing schedule and
    // the send times run on (docs/time.md §1).
    const std::atomic<std::int64_t>* clock_step = nullptr;
};

struct PacketizerStats {
    std::uint64_t data_packets = 0;
    std::uint64_t position_packets = 0;
    std::uint64_t returns_in = 0;            // PointRecords received
    std::uint64_t returns_out_of_range = 0;  // beyond max range / not encodable → no-return
    std::uint64_t returns_bad_channel = 0;   // channel ≥ laser count (ignored)
};

// Velodyne data (and position) packets from the pipeline's returns. Pulse k is firing sequence
// s = k / L, laser = PointRecord.channel (the SpinningPattern order); sequence s fires at
// start + s·period and its rotor azimuth is wrap(s·step) with step = 360°·f·period, exactly as the
// pattern renders. Each block carries the azimuth of its first sequence rounded to 0.01°, the
// timestamp is the µs past the UTC hour of the packet's first firing (§1.6), and a packet is sent
// at the time of its last firing. Position packets go out every model position period
// (start + n·period), before the data packet that follows them in time.
class Packetizer final : public wire::Packetizer {
  public:
    // Throws ConfigError ("velodyne vlp16: …") for an rpm outside the model's range.
    Packetizer(const ModelDescriptor& model, PacketizerOptions options, wire::PacketFn sink);
    // Takes rpm and max range from a sensor model and checks that its scan pattern is this
    // model's (laser count, period, firing offsets, angles); throws ConfigError otherwise.
    Packetizer(const ModelDescriptor& model, ReturnMode mode, const sensor::SensorModel& sensor,
               core::GpsTime start, wire::PacketFn sink, PacketizerOptions options = {});

    void add(std::span<const core::PointRecord> points) override;
    void advance_to(std::uint64_t next_pulse) override;
    void emit_side_packets_until(core::GpsTime t) override;
    void finish() override;

    const PacketizerStats& stats() const { return stats_; }
    const ModelDescriptor& model() const { return model_; }
    const PacketizerOptions& options() const { return opt_; }
    std::uint64_t pulses_per_packet() const { return pulses_per_packet_; }
    // Closed forms the packets follow (tests and the CLI's status line use them).
    core::GpsTime sequence_time(std::uint64_t sequence) const;
    std::uint16_t sequence_azimuth(std::uint64_t sequence) const;  // 0.01° counts
    core::GpsTime packet_send_time(std::uint64_t packet) const;

  private:
    struct Ret {
        float range_m = 0;
        double n = -1;  // photo-electrons (strength)
        std::uint8_t number = 0;
        std::uint8_t reflectivity = 0;
        bool valid() const { return number != 0; }
    };
    struct SlotState {
        Ret strongest, second, last;
    };
    void emit_through(std::uint64_t packet_exclusive);
    void emit_packet();
    void emit_positions_until(core::GpsTime t);
    core::GpsTime stamp(core::GpsTime t) const;  // t + the clock step so far
    static std::uint8_t reflectivity_of(std::uint16_t intensity);

    const ModelDescriptor& model_;
    PacketizerOptions opt_;
    wire::PacketFn sink_;
    double step_deg_ = 0;
    int seqs_per_packet_ = 0;
    std::uint64_t pulses_per_packet_ = 0;
    std::uint64_t packet_ = 0;         // index of the packet being filled
    std::vector<SlotState> slots_;     // seqs_per_packet × lasers
    std::uint64_t position_next_ = 0;  // index of the next position packet
    bool finished_ = false;
    PacketizerStats stats_;
    std::array<std::uint8_t, kDataPacketSize> buf_{};
    std::array<std::uint8_t, kPositionPacketSize> pos_buf_{};
};

}  // namespace mirage::velodyne
