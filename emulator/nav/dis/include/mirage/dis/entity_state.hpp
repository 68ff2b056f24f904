// SPDX-License-Identifier: Apache-2.0
// DIS Entity State PDUs (IEEE 1278.1, versions 6 and 7): the platform pose a constructive
// simulation broadcasts, as one more navigation source (docs/dis.md). Big-endian, 144 bytes plus
// 16 per variable parameter record.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "mirage/core/time.hpp"
#include "mirage/nav/decode_counters.hpp"

namespace mirage::dis {

inline constexpr std::size_t kEntityStateSize = 144;  // without variable parameter records
inline constexpr std::size_t kParameterRecordSize = 16;
inline constexpr std::uint8_t kEntityStatePdu = 1;
inline constexpr std::uint8_t kEntityInformationFamily = 1;

struct EntityId {
    std::uint16_t site = 0, application = 0, entity = 0;
    bool operator==(const EntityId&) const = default;
};

// The fields Mirage reads, in the PDU's own frames: location in ECEF (m), velocity and
// dead-reckoning acceleration in ECEF for algorithms 0–5 and in body axes for 6–9 (m/s, m/s²),
// orientation ψ, θ, φ (rad: about ECEF z, then the new y, then the new x), angular velocity in body
// axes (rad/s, x forward, y right, z down).
struct EntityState {
    std::uint8_t version = 7;
    std::uint8_t exercise = 1;
    std::uint32_t timestamp = 0;  // DIS units: see decode_timestamp()
    EntityId id;
    std::uint8_t force = 0;
    std::uint8_t parameter_records = 0;
    Eigen::Vector3f velocity{Eigen::Vector3f::Zero()};
    Eigen::Vector3d location{Eigen::Vector3d::Zero()};
    float psi = 0, theta = 0, phi = 0;
    std::uint32_t appearance = 0;
    std::uint8_t dr_algorithm = 1;  // 1 static … 9 FVB (dead_reckoning.hpp)
    Eigen::Vector3f dr_acceleration{Eigen::Vector3f::Zero()};
    Eigen::Vector3f dr_angular_velocity{Eigen::Vector3f::Zero()};
    std::array<char, 11> marking{};
    std::uint32_t capabilities = 0;
};

// What a datagram was, checked in this order (length, header, ids, fields).
enum class Status : std::uint8_t {
    Ok,
    Short,          // under 12 header bytes, or under 144 bytes or the length the header
                    // states (a PDU cut short however long it claims to be)
    BadLength,      // the header's length is not 144 + 16·N for the PDU's N
    BadVersion,     // protocol version other than 6 or 7
    OtherPdu,       // a valid header of another PDU type or family
    OtherExercise,  // an Entity State PDU of an exercise the filter does not take
    OtherEntity,    // or of another entity
    BadField,       // NaN/Inf, a location off the Earth's scale, a dead-reckoning algorithm
                    // outside 0–9
};

// Which PDUs a decoder takes: those of one exercise and entity when set.
struct Filter {
    std::optional<std::uint8_t> exercise;
    std::optional<EntityId> entity;
};

// What DIS adds to the common counters.
struct DisCounters {
    std::uint64_t other_pdu = 0;
    std::uint64_t other_exercise = 0;
    std::uint64_t other_entity = 0;
};

// Decodes one UDP datagram (one PDU; trailing bytes past the stated length are ignored, as a
// PDU header says its own length). Never throws; every outcome is counted.
class EntityStateDecoder {
  public:
    explicit EntityStateDecoder(Filter filter = {}) : filter_(filter) {}
    Status decode(std::span<const std::uint8_t> datagram, EntityState& out);
    // From now on, only this entity (a source that locks onto the first entity it hears).
    void follow(const EntityId& id) { filter_.entity = id; }
    const Filter& filter() const { return filter_; }
    const nav::DecodeCounters& counters() const { return counters_; }
    const DisCounters& dis_counters() const { return dis_; }

  private:
    Filter filter_;
    nav::DecodeCounters counters_;
    DisCounters dis_;
};

// The PDU's bytes (no variable parameter records: parameter_records is written as 0).
std::vector<std::uint8_t> encode(const EntityState& s);

// DIS timestamps count 2³¹ units per hour (≈ 1.676 µs) in their top 31 bits; the lowest bit says
// absolute (1: the sender's clock is synchronised to UTC) or relative. Encoding wraps any time
// into the hour (negative ones too).
struct Timestamp {
    double seconds_past_hour = 0;
    bool absolute = false;
};
Timestamp decode_timestamp(std::uint32_t raw);
std::uint32_t encode_timestamp(double seconds_past_hour, bool absolute);
// Seconds from `earlier` to `later`, both past the hour, across at most one hourly rollover:
// the result lies in [−1800, 1800) s.
double seconds_between(double earlier, double later);
// UTC seconds past the hour of a GPS time (what an absolute timestamp carries).
double utc_seconds_past_hour(core::GpsTime t);

}  // namespace mirage::dis
