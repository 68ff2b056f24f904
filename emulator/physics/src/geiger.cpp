// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/geiger.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "mirage/core/error.hpp"

namespace mirage::physics {

EventRate::EventRate(std::span<const double> signal, double noise_per_bin, double bin_ns)
    : noise_(noise_per_bin), bin_ns_(bin_ns) {
    if (!(bin_ns > 0.0) || !std::isfinite(bin_ns))
        throw ConfigError("Geiger-mode gate: the bin width " + std::to_string(bin_ns) +
                          " ns must be > 0");
    if (!(noise_per_bin >= 0.0) || !std::isfinite(noise_per_bin))
        throw ConfigError("Geiger-mode gate: the noise per bin " + std::to_string(noise_per_bin) +
                          " must be ≥ 0");
    prefix_.resize(signal.size() + 1);
    prefix_[0] = 0.0;
    for (std::size_t k = 0; k < signal.size(); ++k) {
        if (!(signal[k] >= 0.0) || !std::isfinite(signal[k]))
            throw ConfigError("Geiger-mode gate: bin " + std::to_string(k) +
                              " expects a negative or non-finite signal");
        prefix_[k + 1] = prefix_[k] + signal[k] + noise_per_bin;
    }
}

double EventRate::signal_share(std::size_t k) const {
    const double n = in(k);
    return n > 0.0 ? std::max(0.0, 1.0 - noise_ / n) : 0.0;
}

double EventRate::time_at(double level) const {
    // The first boundary at or above the level closes the bin it falls in; a bin it crosses has
    // n_k > 0, so the division is safe.
    const auto it = std::lower_bound(prefix_.begin() + 1, prefix_.end(), level);
    if (it == prefix_.end()) return std::numeric_limits<double>::infinity();
    const auto k = static_cast<std::size_t>(it - prefix_.begin()) - 1;
    const double n = prefix_[k + 1] - prefix_[k];
    const double f = n > 0.0 ? std::clamp((level - prefix_[k]) / n, 0.0, 1.0) : 0.0;
    return (double(k) + f) * bin_ns_;
}

double EventRate::level_at(double t_ns) const {
    if (!(t_ns > 0.0)) return 0.0;
    const double x = t_ns / bin_ns_;
    if (x >= double(bins())) return total();
    const auto k = static_cast<std::size_t>(x);
    return prefix_[k] + (x - double(k)) * (prefix_[k + 1] - prefix_[k]);
}

double EventRate::first_event_probability(std::size_t k) const {
    return std::exp(-prefix_[k]) * -std::expm1(-(prefix_[k + 1] - prefix_[k]));
}

std::size_t first_event_bin(const EventRate& rate, double u) {
    const double level = -std::log(u);
    if (level > rate.total()) return rate.bins();
    const double t = rate.time_at(level);
    return std::min(rate.bins() - 1, static_cast<std::size_t>(t / rate.bin_ns()));
}

namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();

// A detection at t of kind `kind`, jittered, and the afterpulse it may release (kNever if none).
double detect(double t, EventKind kind, const GeigerPixel& pixel, core::PulseRng& rng,
              std::vector<GeigerEvent>& out) {
    const double jitter = pixel.jitter_ns > 0.0 ? pixel.jitter_ns * rng.normal() : 0.0;
    out.push_back({t + jitter, kind});
    if (!(pixel.afterpulse_p > 0.0) || rng.uniform() >= pixel.afterpulse_p) return kNever;
    return t - pixel.afterpulse_ns * std::log(rng.uniform());
}

}  // namespace

void geiger_events(const EventRate& rate, const GeigerPixel& pixel, core::PulseRng& rng,
                   std::size_t max_events, std::vector<GeigerEvent>& out) {
    out.clear();
    const DeadTime dead = pixel.dead;
    double level = -std::log(rng.uniform());  // Λ of the next primary event
    double armed_at = 0.0;                    // the pixel fires from this time on
    double afterpulse = kNever;               // a trapped carrier's release
    while (out.size() < max_events) {
        // Non-paralyzable: primary events while dead are lost, and the next after re-arming lies
        // Exp(1) beyond Λ(armed_at) (the process has no memory).
        if (!dead.paralyzable && level < rate.level_at(armed_at))
            level = rate.level_at(armed_at) - std::log(rng.uniform());
        const double primary = level <= rate.total() ? rate.time_at(level) : kNever;
        const double next = std::min(primary, afterpulse);
        if (!(next < rate.gate_ns())) return;
        if (afterpulse < primary) {
            afterpulse = kNever;
            if (next < armed_at) continue;  // released while dead: lost
            armed_at = next + dead.ns;
            afterpulse = detect(next, EventKind::Afterpulse, pixel, rng, out);
            continue;
        }
        if (next >= armed_at) {
            const auto bin =
                std::min(rate.bins() - 1, static_cast<std::size_t>(next / rate.bin_ns()));
            const bool signal = rng.uniform() < rate.signal_share(bin);
            armed_at = next + dead.ns;
            afterpulse = std::min(
                afterpulse,
                detect(next, signal ? EventKind::Signal : EventKind::Noise, pixel, rng, out));
        } else {  // paralyzable: a primary event while dead restarts the dead time
            armed_at = next + dead.ns;
        }
        level -= std::log(rng.uniform());
    }
}

std::vector<double> coates(std::span<const std::uint64_t> histogram, std::uint64_t gates) {
    std::vector<double> n(histogram.size());
    std::uint64_t fired = 0;
    for (std::size_t k = 0; k < histogram.size(); ++k) {
        const std::uint64_t armed = gates > fired ? gates - fired : 0;
        n[k] = armed > 0 ? -std::log1p(-double(histogram[k]) / double(armed))
                         : std::numeric_limits<double>::quiet_NaN();
        fired += histogram[k];
    }
    return n;
}

double observed_rate(double rate_per_ns, DeadTime dead) {
    const double x = rate_per_ns * dead.ns;
    return dead.paralyzable ? rate_per_ns * std::exp(-x) : rate_per_ns / (1.0 + x);
}

}  // namespace mirage::physics
