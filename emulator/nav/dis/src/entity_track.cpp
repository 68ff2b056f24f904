// SPDX-License-Identifier: Apache-2.0
// A DIS entity as a navigation source (docs/dis.md §6).
#include "mirage/dis/entity_track.hpp"

#include <cmath>

#include "mirage/dis/dead_reckoning.hpp"
#include "mirage/dis/dis_sample.hpp"

namespace mirage::dis {
namespace {

std::int64_t ns_of(double seconds) { return std::llround(seconds * 1e9); }

}  // namespace

EntityTrack::EntityTrack(TrackConfig config) : cfg_(config), decoder_(config.filter) {}

void EntityTrack::feed(std::span<const std::uint8_t> datagram, core::GpsTime now,
                       const nav::SampleFn& fn) {
    EntityState s;
    if (decoder_.decode(datagram, s) != Status::Ok) return;
    if (!decoder_.filter().entity) decoder_.follow(s.id);
    const core::GpsTime t = resolve(s.timestamp, now);
    if (base_ && t < base_->t) {
        ++counters_.out_of_order;
        return;
    }
    base_ = Base{s, t};
    last_pdu_ = now;
    silent_ = false;
    ++counters_.accepted;
    emit(now, fn);
}

void EntityTrack::tick(core::GpsTime now, const nav::SampleFn& fn) {
    if (!base_) return;
    if (timed_out(now)) {
        if (!silent_) ++counters_.timeouts;
        silent_ = true;
        return;
    }
    if (last_sample_ && now - *last_sample_ < cfg_.step) return;
    emit(now, fn);
}

bool EntityTrack::timed_out(core::GpsTime now) const {
    return base_ && now - last_pdu_ > cfg_.timeout;
}

void EntityTrack::emit(core::GpsTime now, const nav::SampleFn& fn) {
    const double dt = double((now - base_->t).count()) * 1e-9;
    last_sample_ = now;
    ++counters_.dr_samples;
    fn(to_sample(dead_reckon(base_->state, dt), now));
}

core::GpsTime EntityTrack::resolve(std::uint32_t raw, core::GpsTime now) {
    const Timestamp ts = decode_timestamp(raw);
    if (!ts.absolute) return resolve_relative(ts.seconds_past_hour, now);
    // The sender's UTC time within the hour, in the hour nearest to ours.
    const double ahead = seconds_between(utc_seconds_past_hour(now), ts.seconds_past_hour);
    return now + core::Nanos(ns_of(ahead));
}

core::GpsTime EntityTrack::resolve_relative(double seconds_past_hour, core::GpsTime now) {
    const std::int64_t now_ns = now.time_since_epoch().count();
    if (!rel_) {
        rel_.emplace();
        rel_->last_seconds = seconds_past_hour;
        rel_->unwrapped_ns = ns_of(seconds_past_hour);
    } else {
        rel_->unwrapped_ns += ns_of(seconds_between(rel_->last_seconds, seconds_past_hour));
        rel_->last_seconds = seconds_past_hour;
    }
    const std::int64_t offset = rel_->envelope.add(now_ns - rel_->unwrapped_ns, now_ns);
    return core::GpsTime(core::Nanos(rel_->unwrapped_ns + offset));
}

nav::DecodeCounters EntityTrack::counters() const {
    nav::DecodeCounters c = decoder_.counters();
    c.samples = counters_.dr_samples;
    return c;
}

}  // namespace mirage::dis
