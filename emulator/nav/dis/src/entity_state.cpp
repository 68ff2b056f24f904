// SPDX-License-Identifier: Apache-2.0
// Entity State PDU decoding and encoding (docs/dis.md §1): one place checks a datagram, in the
// order length, header, ids, fields.
#include "mirage/dis/entity_state.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace mirage::dis {
namespace {

// The unsigned integer of T's size, which big-endian reads and writes shift through.
template <typename T>
using Bits = std::conditional_t<sizeof(T) == 2, std::uint16_t,
                                std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>;

// Big-endian reads and writes at byte offsets (the PDU's layout, docs/dis.md §1).
template <typename T>
T get(std::span<const std::uint8_t> b, std::size_t at) {
    Bits<T> u = 0;
    for (std::size_t i = 0; i < sizeof(T); ++i) u = static_cast<Bits<T>>((u << 8) | b[at + i]);
    return std::bit_cast<T>(u);
}

template <typename T>
void put(std::vector<std::uint8_t>& b, std::size_t at, T value) {
    auto u = std::bit_cast<Bits<T>>(value);
    for (std::size_t i = sizeof(T); i-- > 0;) {
        b[at + i] = static_cast<std::uint8_t>(u & 0xFF);
        u = static_cast<Bits<T>>(u >> 8);
    }
}

// Locations farther than this from the Earth's centre are not a platform's (the Moon is 3.8e8 m).
constexpr double kMaxLocationM = 1e9;

void read_fields(std::span<const std::uint8_t> b, EntityState& s) {
    s.version = b[0];
    s.exercise = b[1];
    s.timestamp = get<std::uint32_t>(b, 4);
    s.id = {get<std::uint16_t>(b, 12), get<std::uint16_t>(b, 14), get<std::uint16_t>(b, 16)};
    s.force = b[18];
    s.parameter_records = b[19];
    for (int a = 0; a < 3; ++a) {
        const auto k = static_cast<std::size_t>(a);
        s.velocity[a] = get<float>(b, 36 + 4 * k);
        s.location[a] = get<double>(b, 48 + 8 * k);
        s.dr_acceleration[a] = get<float>(b, 104 + 4 * k);
        s.dr_angular_velocity[a] = get<float>(b, 116 + 4 * k);
    }
    s.psi = get<float>(b, 72);
    s.theta = get<float>(b, 76);
    s.phi = get<float>(b, 80);
    s.appearance = get<std::uint32_t>(b, 84);
    s.dr_algorithm = b[88];
    std::memcpy(s.marking.data(), b.data() + 129, s.marking.size());
    s.capabilities = get<std::uint32_t>(b, 140);
}

}  // namespace

Status EntityStateDecoder::decode(std::span<const std::uint8_t> d, EntityState& out) {
    const auto fail = [&](Status s, std::uint64_t& counter) {
        ++counter;
        return s;
    };
    if (d.size() < 12) return fail(Status::Short, counters_.truncated);
    const std::uint16_t length = get<std::uint16_t>(d, 8);
    if (d[0] != 6 && d[0] != 7) return fail(Status::BadVersion, counters_.unsupported);
    if (d[2] != kEntityStatePdu || d[3] != kEntityInformationFamily)
        return fail(Status::OtherPdu, dis_.other_pdu);
    if (d.size() < kEntityStateSize || d.size() < length)
        return fail(Status::Short, counters_.truncated);
    if (length != kEntityStateSize + kParameterRecordSize * d[19])
        return fail(Status::BadLength, counters_.truncated);
    if (filter_.exercise && d[1] != *filter_.exercise)
        return fail(Status::OtherExercise, dis_.other_exercise);
    const EntityId id{get<std::uint16_t>(d, 12), get<std::uint16_t>(d, 14),
                      get<std::uint16_t>(d, 16)};
    if (filter_.entity && !(id == *filter_.entity))
        return fail(Status::OtherEntity, dis_.other_entity);
    EntityState s;
    read_fields(d, s);
    const bool ok = s.velocity.allFinite() && s.location.allFinite() &&
                    s.dr_acceleration.allFinite() && s.dr_angular_velocity.allFinite() &&
                    std::isfinite(s.psi) && std::isfinite(s.theta) && std::isfinite(s.phi) &&
                    s.location.norm() < kMaxLocationM && s.dr_algorithm <= 9;
    if (!ok) return fail(Status::BadField, counters_.invalid_field);
    out = s;
    ++counters_.messages_ok;
    return Status::Ok;
}

std::vector<std::uint8_t> encode(const EntityState& s) {
    std::vector<std::uint8_t> b(kEntityStateSize, 0);
    b[0] = s.version;
    b[1] = s.exercise;
    b[2] = kEntityStatePdu;
    b[3] = kEntityInformationFamily;
    put(b, 4, s.timestamp);
    put(b, 8, static_cast<std::uint16_t>(kEntityStateSize));
    put(b, 12, s.id.site);
    put(b, 14, s.id.application);
    put(b, 16, s.id.entity);
    b[18] = s.force;
    for (int a = 0; a < 3; ++a) {
        const auto k = static_cast<std::size_t>(a);
        put(b, 36 + 4 * k, s.velocity[a]);
        put(b, 48 + 8 * k, s.location[a]);
        put(b, 104 + 4 * k, s.dr_acceleration[a]);
        put(b, 116 + 4 * k, s.dr_angular_velocity[a]);
    }
    put(b, 72, s.psi);
    put(b, 76, s.theta);
    put(b, 80, s.phi);
    put(b, 84, s.appearance);
    b[88] = s.dr_algorithm;
    b[128] = 1;  // marking character set: ASCII
    std::memcpy(b.data() + 129, s.marking.data(), s.marking.size());
    put(b, 140, s.capabilities);
    return b;
}

namespace {
constexpr double kUnitsPerHour = 2147483648.0;  // 2³¹
}

Timestamp decode_timestamp(std::uint32_t raw) {
    return {double(raw >> 1) * 3600.0 / kUnitsPerHour, (raw & 1u) != 0};
}

std::uint32_t encode_timestamp(double seconds_past_hour, bool absolute) {
    if (!std::isfinite(seconds_past_hour)) seconds_past_hour = 0;  // (a caller's bug: no UB)
    double s = std::fmod(seconds_past_hour, 3600.0);
    if (s < 0) s += 3600.0;  // −0.5 s is 3 599.5 s past the previous hour
    const double units = std::floor(s / 3600.0 * kUnitsPerHour);
    const auto u = static_cast<std::uint32_t>(std::clamp(units, 0.0, kUnitsPerHour - 1.0));
    return (u << 1) | (absolute ? 1u : 0u);
}

double seconds_between(double earlier, double later) {
    double d = std::fmod(later - earlier, 3600.0);
    if (d >= 1800.0) d -= 3600.0;
    if (d < -1800.0) d += 3600.0;
    return d;
}

double utc_seconds_past_hour(core::GpsTime t) {
    constexpr std::int64_t kHourNs = 3'600'000'000'000;
    const std::int64_t unix_ns = core::unix_ns_from_gps(t);
    return double(((unix_ns % kHourNs) + kHourNs) % kHourNs) * 1e-9;
}

}  // namespace mirage::dis
