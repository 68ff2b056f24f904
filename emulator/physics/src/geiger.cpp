// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/geiger.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "mirage/core/error.hpp"

namespace mirage::physics {

namespace {

[[noreturn]] void bad_gate(const std::string& what) {
    throw ConfigError("Geiger-mode gate: " + what);
}

std::vector<SignalBin> sparse(std::span<const double> signal) {
    std::vector<SignalBin> out;
    for (std::size_t k = 0; k < signal.size(); ++k) {
        if (!(signal[k] >= 0.0) || !std::isfinite(signal[k]))
            bad_gate("bin " + std::to_string(k) + " expects a negative or non-finite signal");
        if (signal[k] > 0.0) out.push_back({static_cast<std::uint32_t>(k), signal[k]});
    }
    return out;
}

}  // namespace

EventRate::EventRate(std::span<const double> signal, double noise_per_bin, double bin_ns) {
    assign(signal.size(), sparse(signal), noise_per_bin, bin_ns);
}

EventRate::EventRate(std::size_t bins, std::span<const SignalBin> signal, double noise_per_bin,
                     double bin_ns) {
    assign(bins, signal, noise_per_bin, bin_ns);
}

void EventRate::assign(std::size_t bins, std::span<const SignalBin> signal, double noise_per_bin,
                       double bin_ns) {
    if (!(bin_ns > 0.0) || !std::isfinite(bin_ns))
        bad_gate("the bin width " + std::to_string(bin_ns) + " ns must be > 0");
    if (!(noise_per_bin >= 0.0) || !std::isfinite(noise_per_bin))
        bad_gate("the noise per bin " + std::to_string(noise_per_bin) + " must be ≥ 0");
    begin(bins, noise_per_bin, bin_ns);
    std::int64_t last = -1;
    for (const SignalBin& b : signal) {
        if (b.k >= bins || std::int64_t(b.k) <= last)
            bad_gate("signal bin " + std::to_string(b.k) + " out of order or past the gate");
        if (!(b.signal >= 0.0) || !std::isfinite(b.signal))
            bad_gate("bin " + std::to_string(b.k) + " expects a negative or non-finite signal");
        last = b.k;
        add(b.k, b.signal);  // (a bin without signal adds nothing)
    }
    finish();
}

void EventRate::begin(std::size_t bins, double noise_per_bin, double bin_ns) {
    bins_ = bins;
    noise_ = noise_per_bin;
    bin_ns_ = bin_ns;
    key_.clear();
    signal_.clear();
    cum_.assign(1, 0.0);
    end_.clear();
}

void EventRate::add_run(std::int64_t k0, double scale, const double* w, std::size_t n) {
    const std::int64_t lo = std::max<std::int64_t>(0, -k0);
    const std::int64_t hi = std::min<std::int64_t>(std::int64_t(n), std::int64_t(bins_) - k0);
    if (lo >= hi) return;
    if (!key_.empty() && k0 + lo <= std::int64_t(key_.back())) {  // merges: one by one
        for (std::int64_t j = lo; j < hi; ++j)
            add(static_cast<std::uint32_t>(k0 + j), scale * w[j]);
        return;
    }
    std::size_t m = key_.size();
    const auto most = m + static_cast<std::size_t>(hi - lo);
    key_.resize(most);
    signal_.resize(most);
    end_.resize(most);
    cum_.resize(most + 1);
    const double base = cum_[m];
    double shares = 0;  // the run's shares taken so far, summed in order
    for (std::int64_t j = lo; j < hi; ++j) {
        const double s = scale * w[j];
        if (!(s > 0.0) || !(s < kHuge)) continue;
        const auto k = static_cast<std::uint32_t>(k0 + j);
        shares += w[j];
        const double c = std::fma(scale, shares, base);
        key_[m] = k;
        signal_[m] = s;
        cum_[m + 1] = c;
        end_[m] = std::fma(noise_, double(k + 1), c);
        ++m;
    }
    key_.resize(m);
    signal_.resize(m);
    end_.resize(m);
    cum_.resize(m + 1);
}

std::size_t EventRate::entry(std::size_t k) const {
    return static_cast<std::size_t>(
        std::lower_bound(key_.begin(), key_.end(), static_cast<std::uint32_t>(k)) - key_.begin());
}

double EventRate::before(std::size_t k) const { return noise_ * double(k) + cum_[entry(k)]; }

double EventRate::in(std::size_t k) const {
    const std::size_t j = entry(k);
    return noise_ + (j < key_.size() && key_[j] == k ? signal_[j] : 0.0);
}

double EventRate::signal_share(std::size_t k) const {
    const double n = in(k);
    return n > 0.0 ? std::max(0.0, 1.0 - noise_ / n) : 0.0;
}

// The first signal bin whose end lies above the level holds it, or the noise-only stretch
// before that bin (after the previous one) does; past the last signal bin, the noise after it.
double EventRate::time_at(double level) const {
    if (!(level < total_)) return std::numeric_limits<double>::infinity();
    const auto j =
        static_cast<std::size_t>(std::upper_bound(end_.begin(), end_.end(), level) - end_.begin());
    if (j < key_.size()) {
        const double start = std::fma(noise_, double(key_[j]), cum_[j]);
        if (level >= start)
            return (double(key_[j]) + std::min(1.0, (level - start) / (noise_ + signal_[j]))) *
                   bin_ns_;
    }
    if (!(noise_ > 0.0)) return double(j < key_.size() ? key_[j] : bins_) * bin_ns_;
    return std::min(double(bins_), (level - cum_[j]) / noise_) * bin_ns_;
}

double EventRate::level_at(double t_ns) const {
    if (!(t_ns > 0.0)) return 0.0;
    const double x = t_ns / bin_ns_;
    if (x >= double(bins_)) return total_;
    const auto k = static_cast<std::size_t>(x);
    return before(k) + (x - double(k)) * in(k);
}

double EventRate::first_event_probability(std::size_t k) const {
    return std::exp(-before(k)) * -std::expm1(-in(k));
}

std::size_t first_event_bin(const EventRate& rate, double u) {
    const double level = -std::log(u);
    if (!(level < rate.total())) return rate.bins();
    const double t = rate.time_at(level);
    return std::min(rate.bins() - 1, static_cast<std::size_t>(t / rate.bin_ns()));
}

namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();

// A detection at t of kind `kind`, jittered (reported unless `report` is false), and the
// afterpulse it may release (kNever if none).
double detect(double t, EventKind kind, const GeigerPixel& pixel, core::PulseRng& rng, bool report,
              std::vector<GeigerEvent>& out) {
    const double jitter = pixel.jitter_ns > 0.0 ? pixel.jitter_ns * rng.normal() : 0.0;
    if (report) out.push_back({t + jitter, kind});
    if (!(pixel.afterpulse_p > 0.0) || rng.uniform() >= pixel.afterpulse_p) return kNever;
    return t - pixel.afterpulse_ns * std::log(rng.uniform());
}

// A paralyzable pixel dead until `armed_at` after a primary event at `t`: when it re-arms. Each
// step reveals the primary events up to where the pixel would re-arm (or the rate's end): if
// there are any, the last of them, drawn backwards (Λ(end) − Λ(last) is Exp(1); beyond the
// step's span, there are none), restarts the dead time, and the next step reveals from there.
// So a dead span costs a step per dead time, not a draw per primary event: a sunlit or strong
// return holds 10⁵ and more in a gate (docs/photon-counting.md §2, dead time).
double paralyzed_until(const EventRate& rate, double t, double armed_at, double dead_ns,
                       core::PulseRng& rng) {
    // Primary events are known up to `known`, where Λ is `from`.
    for (double known = t, from = rate.level_at(t);;) {
        const double end = std::min(armed_at, rate.gate_ns());
        if (!(known < end)) return armed_at;
        const double to = rate.level_at(end);
        const double back = -std::log(rng.uniform());
        if (!(back < to - from)) return armed_at;  // none: re-armed
        // Within the span: rounding may put `to − back` at the rate's end (time_at: +inf).
        armed_at = std::max(armed_at, std::clamp(rate.time_at(to - back), known, end) + dead_ns);
        known = end;
        from = to;
    }
}

// The draw shared by the gated and free-running windows. Gated (`track` false): the pixel starts
// armed, every detection is reported, and the draw ends at the max_events-th. Free-running: it
// goes on to the rate's end, reporting those before report_ns, and returns the re-arming time.
double draw_events(const EventRate& rate, const GeigerPixel& pixel, core::PulseRng& rng,
                   double level, const GeigerWindow& w, bool track, std::vector<GeigerEvent>& out) {
    out.clear();
    const DeadTime dead = pixel.dead;
    double armed_at = w.armed_from_ns;  // the pixel fires from this time on
    double afterpulse = kNever;         // a trapped carrier's release
    const auto report = [&](double t) { return t < w.report_ns && out.size() < w.max_events; };
    while (track || out.size() < w.max_events) {
        // Dead past the rate's end: nothing more can be detected (an afterpulse then is lost
        // too), so nothing more is drawn; a paralyzable pixel tracked to the end still takes
        // the primary events that restart its dead time.
        if (!(armed_at < rate.gate_ns()) && !(track && dead.paralyzable)) return armed_at;
        // Non-paralyzable: primary events while dead are lost, and the next after re-arming lies
        // Exp(1) beyond Λ(armed_at) (the process has no memory).
        if (!dead.paralyzable && level < rate.level_at(armed_at))
            level = rate.level_at(armed_at) - std::log(rng.uniform());
        const double primary = level <= rate.total() ? rate.time_at(level) : kNever;
        const double next = std::min(primary, afterpulse);
        if (!(next < rate.gate_ns())) return armed_at;
        if (afterpulse < primary) {
            afterpulse = kNever;
            if (next < armed_at) continue;  // released while dead: lost
            armed_at = next + dead.ns;
            afterpulse = detect(next, EventKind::Afterpulse, pixel, rng, report(next), out);
            continue;
        }
        if (next >= armed_at) {
            const auto bin =
                std::min(rate.bins() - 1, static_cast<std::size_t>(next / rate.bin_ns()));
            const bool signal = rng.uniform() < rate.signal_share(bin);
            armed_at = next + dead.ns;
            afterpulse =
                std::min(afterpulse, detect(next, signal ? EventKind::Signal : EventKind::Noise,
                                            pixel, rng, report(next), out));
        } else {  // paralyzable: a primary event while dead restarts the dead time
            armed_at = std::max(armed_at, next + dead.ns);
        }
        if (dead.paralyzable) {  // the primary events up to re-arming, then the next one
            if (!track && out.size() >= w.max_events) break;  // gated: all drawn
            armed_at = paralyzed_until(rate, next, armed_at, dead.ns, rng);
            level = rate.level_at(std::min(armed_at, rate.gate_ns())) - std::log(rng.uniform());
            continue;
        }
        if (!track && out.size() >= w.max_events) break;  // gated: all drawn
        level -= std::log(rng.uniform());
    }
    return armed_at;
}

}  // namespace

double first_level(core::PulseRng& rng) { return -std::log(rng.uniform()); }

void geiger_events(const EventRate& rate, const GeigerPixel& pixel, core::PulseRng& rng,
                   std::size_t max_events, std::vector<GeigerEvent>& out) {
    const double level = first_level(rng);
    geiger_events(rate, pixel, rng, level, max_events, out);
}

// `level`: Λ of the next primary event.
void geiger_events(const EventRate& rate, const GeigerPixel& pixel, core::PulseRng& rng,
                   double level, std::size_t max_events, std::vector<GeigerEvent>& out) {
    const GeigerWindow gated{0.0, kNever, max_events};
    (void)draw_events(rate, pixel, rng, level, gated, false, out);
}

double geiger_events(const EventRate& rate, const GeigerPixel& pixel, core::PulseRng& rng,
                     double level, const GeigerWindow& window, std::vector<GeigerEvent>& out) {
    return draw_events(rate, pixel, rng, level, window, true, out);
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
