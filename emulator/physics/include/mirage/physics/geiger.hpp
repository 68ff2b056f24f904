// SPDX-License-Identifier: Apache-2.0
// Geiger-mode detection (docs/photon-counting.md §2): a pixel's avalanche photodiode fires on its
// first primary event and is then dead for a while. The expected primary events per time bin
// (signal times the photon detection efficiency, background and dark counts) make a
// piecewise-constant rate over the gate; events are drawn exactly by inverting its integral.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "mirage/core/rng.hpp"

namespace mirage::physics {

// A pixel's gate as bins of bin_ns from its opening, each expecting signal S_k (≥ 0) plus a
// constant noise (background and dark) of primary events, n_k = S_k + noise; Λ(t) their integral:
// Λ_k = Σ_{j<k} n_j at bin boundaries, linear inside a bin.
class EventRate {
  public:
    EventRate(std::span<const double> signal, double noise_per_bin, double bin_ns);
    std::size_t bins() const { return prefix_.size() - 1; }
    double bin_ns() const { return bin_ns_; }
    double gate_ns() const { return bin_ns_ * double(bins()); }
    double total() const { return prefix_.back(); }            // Λ over the whole gate
    double before(std::size_t k) const { return prefix_[k]; }  // Λ_k
    double in(std::size_t k) const { return prefix_[k + 1] - prefix_[k]; }  // n_k
    // The share of bin k's events that are signal, S_k/n_k (0 for an empty bin).
    double signal_share(std::size_t k) const;
    // The time (ns from the gate's opening) where Λ reaches `level`; +inf past the gate.
    double time_at(double level) const;
    // Λ(t); total() from the gate's end on.
    double level_at(double t_ns) const;
    // P(the first primary event falls in bin k) = e^(−Λ_k)·(1 − e^(−n_k)).
    double first_event_probability(std::size_t k) const;

  private:
    std::vector<double> prefix_;
    double noise_, bin_ns_;
};

struct DeadTime {
    double ns = 0;             // after a detection the pixel cannot fire for this long
    bool paralyzable = false;  // a primary event while dead restarts it
};

// A pixel's own effects beyond the Poisson arrivals.
struct GeigerPixel {
    DeadTime dead;
    double jitter_ns = 0;      // σ of the normal added to each reported time
    double afterpulse_p = 0;   // probability that a detection releases an afterpulse
    double afterpulse_ns = 0;  // mean of its exponential delay after the detection
};

enum class EventKind : std::uint8_t { Signal, Noise, Afterpulse };

struct GeigerEvent {
    double t_ns = 0;  // reported time from the gate's opening (jitter included)
    EventKind kind = EventKind::Signal;
};

// The bin of the first primary event for the uniform u: the first k with Λ_(k+1) ≥ −ln u, or
// bins() when Λ over the gate falls short (no event).
std::size_t first_event_bin(const EventRate& rate, double u);

// The pixel's detections in one gate, in order, at most max_events, into `out`. Successive
// primary events lie at Λ(t) = Λ(t_prev) + E, E = −ln u (the first uniform of `rng` is the first
// event's). One while the pixel is armed is detected (signal with probability S_k/n_k, else
// noise) and starts the dead time; one while it is dead is lost (non-paralyzable: the search
// restarts where the pixel re-arms, exact since the process has no memory) or restarts the dead
// time (paralyzable). A detection releases an afterpulse with probability afterpulse_p after an
// exponential delay; it fires the pixel if armed then, else it is lost. Each reported time gets
// the jitter.
void geiger_events(const EventRate& rate, const GeigerPixel& pixel, core::PulseRng& rng,
                   std::size_t max_events, std::vector<GeigerEvent>& out);

// Coates' correction (Coates 1968): from first-event counts h_k over `gates` gates, the expected
// events per bin n̂_k = −ln(1 − h_k/(gates − Σ_{j<k} h_j)); NaN where no gate was armed.
std::vector<double> coates(std::span<const std::uint64_t> histogram, std::uint64_t gates);

// The counting rate of a free-running detector under a Poisson rate (per ns) with its dead
// time: rate/(1 + rate·τ) non-paralyzable, rate·e^(−rate·τ) paralyzable.
double observed_rate(double rate_per_ns, DeadTime dead);

}  // namespace mirage::physics
