// SPDX-License-Identifier: Apache-2.0
// libFuzzer target (Clang): an Entity State PDU decoder must return a status and count it,
// never crash or read out of bounds; a decoded PDU is finite, re-encodes to bytes that decode to
// the same state, and dead-reckons to a finite pose; followed as a navigation source, its
// samples are finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "mirage/dis/dead_reckoning.hpp"
#include "mirage/dis/entity_state.hpp"
#include "mirage/dis/entity_track.hpp"

namespace {

// Through the source: fed at a fixed time, then stepped a second on.
void follow(std::span<const std::uint8_t> bytes) {
    mirage::dis::EntityTrack track;
    const mirage::core::GpsTime now(std::chrono::seconds(1'400'000'000));
    const auto check = [](const mirage::nav::NavSample& x) {
        if (!std::isfinite(x.lat_deg) || !std::isfinite(x.lon_deg) || !std::isfinite(x.height_m) ||
            !std::isfinite(x.heading_rad) || !x.velocity_ned_mps.allFinite())
            __builtin_trap();
    };
    track.feed(bytes, now, check);
    track.tick(now + std::chrono::seconds(1), check);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> bytes(data, size);
    follow(bytes);
    mirage::dis::EntityStateDecoder any;
    mirage::dis::EntityState s;
    const auto status = any.decode(bytes, s);
    const auto& c = any.counters();
    const auto& d = any.dis_counters();
    const std::uint64_t counted = c.messages_ok + c.truncated + c.unsupported + c.invalid_field +
                                  d.other_pdu + d.other_exercise + d.other_entity;
    if (counted != 1) __builtin_trap();
    if (status != mirage::dis::Status::Ok) return 0;
    if (!s.location.allFinite() || !std::isfinite(s.psi)) __builtin_trap();
    mirage::dis::EntityStateDecoder again;
    mirage::dis::EntityState t;
    if (again.decode(mirage::dis::encode(s), t) != mirage::dis::Status::Ok) __builtin_trap();
    if (t.location != s.location || t.velocity != s.velocity || t.id.entity != s.id.entity)
        __builtin_trap();
    const auto k = mirage::dis::dead_reckon(s, 1.0);
    if (!k.location.allFinite()) __builtin_trap();
    return 0;
}
