// SPDX-License-Identifier: Apache-2.0
// One DIS entity followed as a navigation source (docs/dis.md §6): its last Entity State PDU is
// the dead-reckoning base, evaluated at the host's present time every few milliseconds, so the
// pose buffer holds the dead-reckoned path and the renderer's firing times fall between its
// samples. Silent for longer than the timeout, the entity gives no samples: poses go stale.
#pragma once
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>

#include "mirage/core/time.hpp"
#include "mirage/dis/entity_state.hpp"
#include "mirage/nav/decode_counters.hpp"
#include "mirage/nav/lower_envelope.hpp"
#include "mirage/nav/nav_sample.hpp"

namespace mirage::dis {

struct TrackConfig {
    // Exercise and entity; without an entity, the first entity heard is followed.
    Filter filter;
    // No PDU for this long: the entity is stale (IEEE 1278.1's default heartbeat of 5 s times
    // its timeout multiplier 2.4).
    core::Nanos timeout{std::chrono::seconds(12)};
    // Dead-reckoned samples at most this often.
    core::Nanos step{std::chrono::milliseconds(5)};
};

struct TrackCounters {
    std::uint64_t accepted = 0;      // PDUs that became the dead-reckoning base
    std::uint64_t out_of_order = 0;  // PDUs older than the base (reordered datagrams)
    std::uint64_t timeouts = 0;      // times the entity fell silent for the timeout
    std::uint64_t dr_samples = 0;    // samples given (at arrivals and between them)
};

class EntityTrack {
  public:
    explicit EntityTrack(TrackConfig config = {});

    // One datagram received at `now` (GPS time read from the host's UTC clock). A PDU of the
    // entity not older than the base becomes the base; a sample dead-reckoned to `now` is given.
    void feed(std::span<const std::uint8_t> datagram, core::GpsTime now, const nav::SampleFn& fn);
    // The base dead-reckoned to `now`, once `step` has passed since the last sample, unless the
    // entity has timed out.
    void tick(core::GpsTime now, const nav::SampleFn& fn);

    // The GPS time a PDU's timestamp stands for, received at `now` (§3): an absolute timestamp
    // is the UTC hour's nearest to `now`; relative ones are unwrapped across hours and placed by
    // the lower envelope of arrival − timestamp.
    core::GpsTime resolve(std::uint32_t raw_timestamp, core::GpsTime now);

    bool timed_out(core::GpsTime now) const;
    core::Nanos step() const { return cfg_.step; }
    std::optional<EntityId> entity() const { return decoder_.filter().entity; }
    nav::DecodeCounters counters() const;
    const DisCounters& dis_counters() const { return decoder_.dis_counters(); }
    const TrackCounters& track_counters() const { return counters_; }

  private:
    struct Base {
        EntityState state;
        core::GpsTime t;
    };
    void emit(core::GpsTime now, const nav::SampleFn& fn);
    core::GpsTime resolve_relative(double seconds_past_hour, core::GpsTime now);

    TrackConfig cfg_;
    EntityStateDecoder decoder_;
    std::optional<Base> base_;
    core::GpsTime last_pdu_{};
    std::optional<core::GpsTime> last_sample_;
    bool silent_ = false;
    TrackCounters counters_;
    // Relative timestamps: the unwrapped sender time (ns) and the lower envelope of arrival −
    // sender time over two blocks of 10 s.
    struct Relative {
        Relative() : envelope(10'000'000'000) {}  // (not a member initializer: Clang's optional)
        double last_seconds = 0;
        std::int64_t unwrapped_ns = 0;
        nav::LowerEnvelope envelope;
    };
    std::optional<Relative> rel_;
};

}  // namespace mirage::dis
