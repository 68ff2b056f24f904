// SPDX-License-Identifier: Apache-2.0
// Geiger-mode detection (docs/photon-counting.md §2): a pixel's avalanche photodiode fires on its
// first primary event and is then dead for a while. The expected primary events per time bin
// (signal times the photon detection efficiency, background and dark counts) make a
// piecewise-constant rate over the gate; events are drawn exactly by inverting its integral.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "mirage/core/rng.hpp"

namespace mirage::physics {

// One bin of a gate that expects signal: its index and its signal primary events.
struct SignalBin {
    std::uint32_t k;
    double signal;
};

// A pixel's gate as bins of bin_ns from its opening, each expecting signal S_k (≥ 0) plus a
// constant noise (background and dark) of primary events, n_k = S_k + noise; Λ(t) their integral:
// Λ_k = Σ_{j<k} n_j at bin boundaries, linear inside a bin. Stored sparse (the bins with signal
// and their running sums), so a long gate with a short return costs the return's bins only;
// every query is O(log m) in the m signal bins.
class EventRate {
  public:
    static constexpr double kHuge = 1e300;  // above it a signal is taken as not finite
    // Dense: one signal value per bin (zeros allowed).
    EventRate(std::span<const double> signal, double noise_per_bin, double bin_ns);
    // Sparse: `bins` bins, the signal ones in increasing k, each k < bins at most once.
    EventRate(std::size_t bins, std::span<const SignalBin> signal, double noise_per_bin,
              double bin_ns);
    EventRate() = default;
    // The same over new bins (reuses the storage; the sparse constructor's checks).
    void assign(std::size_t bins, std::span<const SignalBin> signal, double noise_per_bin,
                double bin_ns);
    // In place, for a caller whose signal is its own (the pipeline's, from a checked sensor):
    // begin(), then add() in increasing k (a repeated k adds to its bin), then finish(). It
    // never throws: a k past the gate, out of order, or a signal that is not a finite
    // number > 0, adds nothing. Reuses the storage, so a pixel-pulse allocates nothing.
    void begin(std::size_t bins, double noise_per_bin, double bin_ns);
    void add(std::uint32_t k, double signal) {
        if (!(k < bins_) || !(signal > 0.0) || !(signal < kHuge)) return;
        if (!key_.empty() && k < key_.back()) return;  // out of order: the caller's error
        if (!key_.empty() && key_.back() == k) {
            signal_.back() += signal;
            cum_.back() += signal;
            end_.back() += signal;
            return;
        }
        key_.push_back(k);
        signal_.push_back(signal);
        cum_.push_back(cum_.back() + signal);
        end_.push_back(std::fma(noise_, double(k + 1), cum_.back()));
    }
    // Bins k0 + j for j < n expecting scale·w[j] (a pulse's shares times its photo-electrons),
    // the bins add() would take one by one, in one pass; Λ's signal part at each bin is the sum
    // before the run plus scale times the run's shares so far (one rounding of the product for
    // each bin, not a running sum of products), so gated_first_event finds it without a chain
    // of additions (docs/photon-counting.md §2).
    void add_run(std::int64_t k0, double scale, const double* w, std::size_t n);
    void finish() { total_ = std::fma(noise_, double(bins_), cum_.back()); }
    // The last bin given a signal, or −1.
    std::int64_t last_key() const { return key_.empty() ? -1 : std::int64_t(key_.back()); }
    std::size_t bins() const { return bins_; }
    double bin_ns() const { return bin_ns_; }
    double gate_ns() const { return bin_ns_ * double(bins_); }
    double total() const { return total_; }  // Λ over the whole gate
    double before(std::size_t k) const;      // Λ_k
    double in(std::size_t k) const;          // n_k
    // The share of bin k's events that are signal, S_k/n_k (0 for an empty bin).
    double signal_share(std::size_t k) const;
    // The time (ns from the gate's opening) where Λ reaches `level`; +inf past the gate.
    double time_at(double level) const;
    // Λ(t); total() from the gate's end on.
    double level_at(double t_ns) const;
    // P(the first primary event falls in bin k) = e^(−Λ_k)·(1 − e^(−n_k)).
    double first_event_probability(std::size_t k) const;

  private:
    std::size_t entry(std::size_t k) const;  // signal entries with key < k
    std::vector<std::uint32_t> key_;         // signal bins, increasing
    std::vector<double> signal_;             // their S_k
    std::vector<double> cum_;                // Σ S before entry j (size m + 1)
    std::vector<double> end_;                // Λ at the end of entry j's bin
    std::size_t bins_ = 0;
    double noise_ = 0, bin_ns_ = 1, total_ = 0;
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

// Crosstalk: an avalanche in a neighbouring pixel fired this one (arrays only).
enum class EventKind : std::uint8_t { Signal, Noise, Afterpulse, Crosstalk };

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
// The same with the first event's level Λ = −ln u already drawn (first_level): a caller that
// knows an upper bound of the rate's total can skip building it when the level lies above.
double first_level(core::PulseRng& rng);
void geiger_events(const EventRate& rate, const GeigerPixel& pixel, core::PulseRng& rng,
                   double level, std::size_t max_events, std::vector<GeigerEvent>& out);

// A free-running pixel's window (docs/photon-counting.md §2.1): its rate runs to the next pulse's
// window, the pixel is armed from `armed_from_ns` (a dead time carried from the previous pulse),
// and only detections before `report_ns` (the range gate's close) are reported, at most
// max_events; the later ones still make it dead, so every detection is drawn.
struct GeigerWindow {
    double armed_from_ns = 0;
    double report_ns = 0;
    std::size_t max_events = 1;
};
// The window's reported detections into `out`; returns when the pixel is armed again after its
// last detection (paralyzable: after the last primary event), or armed_from_ns if none.
double geiger_events(const EventRate& rate, const GeigerPixel& pixel, core::PulseRng& rng,
                     double level, const GeigerWindow& window, std::vector<GeigerEvent>& out);

// Coates' correction (Coates 1968): from first-event counts h_k over `gates` gates, the expected
// events per bin n̂_k = −ln(1 − h_k/(gates − Σ_{j<k} h_j)); NaN where no gate was armed.
std::vector<double> coates(std::span<const std::uint64_t> histogram, std::uint64_t gates);

// The counting rate of a free-running detector under a Poisson rate (per ns) with its dead
// time: rate/(1 + rate·τ) non-paralyzable, rate·e^(−rate·τ) paralyzable.
double observed_rate(double rate_per_ns, DeadTime dead);

}  // namespace mirage::physics
