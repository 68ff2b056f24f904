// SPDX-License-Identifier: Apache-2.0
#include "mirage/replay/impairer.hpp"

#include <fmt/format.h>

#include "mirage/core/error.hpp"

namespace mirage::replay {

Impairer::Impairer(const ImpairmentConfig& config) : config_(config), rng_(config.seed) {
    auto rate = [](double r, const char* name) {
        if (!(r >= 0.0 && r <= 1.0))
            throw ConfigError(fmt::format("replay --{} {}: expected a rate in [0, 1]", name, r));
    };
    rate(config.drop, "drop");
    rate(config.duplicate, "duplicate");
    rate(config.reorder, "reorder");
    if (config.drop_burst == 0) throw ConfigError("replay --drop-burst 0: expected at least 1");
    if (config.jitter_ns < 0) throw ConfigError("replay --jitter-us: expected >= 0");
}

// 53 random bits -> [0, 1): the same sequence on every standard library (unlike the
// distributions, whose algorithms are implementation-defined).
bool Impairer::chance(double p) {
    if (p <= 0.0) return false;
    const double u = static_cast<double>(rng_() >> 11) * 0x1.0p-53;
    return u < p;
}

void Impairer::emit(Packet&& p, std::vector<Packet>& out) {
    const bool dup = chance(config_.duplicate);
    if (config_.jitter_ns > 0)
        p.time_ns +=
            static_cast<std::int64_t>(rng_() % static_cast<std::uint64_t>(config_.jitter_ns + 1));
    if (dup) {
        out.push_back(p);
        ++counters_.duplicated;
        ++counters_.out;
    }
    out.push_back(std::move(p));
    ++counters_.out;
}

void Impairer::push(Packet&& p, std::vector<Packet>& out) {
    ++counters_.in;
    if (burst_left_ > 0) {
        --burst_left_;
        ++counters_.dropped;
        return;
    }
    if (chance(config_.drop)) {
        burst_left_ = config_.drop_burst - 1;
        ++counters_.dropped;
        ++counters_.drop_events;
        return;
    }
    if (held_) {
        // Swap: this packet takes the held one's slot in the schedule and vice versa.
        Packet first = std::move(*held_);
        held_.reset();
        std::swap(first.time_ns, p.time_ns);
        ++counters_.reordered;
        emit(std::move(p), out);
        emit(std::move(first), out);
        return;
    }
    if (chance(config_.reorder)) {
        held_ = std::move(p);
        return;
    }
    emit(std::move(p), out);
}

void Impairer::finish(std::vector<Packet>& out) {
    if (held_) {
        Packet p = std::move(*held_);
        held_.reset();
        emit(std::move(p), out);
    }
}

}  // namespace mirage::replay
