// SPDX-License-Identifier: Apache-2.0
// A pulse's expected photo-electrons in time (docs/time-resolved.md §2, §4): each path's arrival
// spread by the emitted pulse's shape and sampled on the digitiser's clock.
#pragma once
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "mirage/sensor/pulse_shape.hpp"

namespace mirage::physics {

// One path's contribution to a pulse (docs/time-resolved.md §2).
struct Arrival {
    std::int64_t delay_ps = 0;  // two-way path time after emission (range = c·t/2)
    float pe = 0;               // expected photo-electrons of the path
    std::uint32_t hit = 0;      // the batch's hit of the path's last surface
};

// Arrivals in order of delay, ties in the order they came (a stable sort): the same order on any
// machine whichever way it is computed. `tmp` is scratch space.
void sort_by_delay(std::vector<Arrival>& arrivals, std::vector<Arrival>& tmp);

// Sorted arrivals in clusters (each from its first arrival to those less than `window_ps` after
// it) replaced by each cluster's two-point Gauss quadrature: two arrivals inside the cluster
// whose photo-electrons, mean delay, variance and third moment are the cluster's, each with the
// cluster's strongest arrival's hit; a cluster of one, or narrower than 1 ps, stays one (at its
// weighted mean). The result stays sorted. docs/time-resolved.md §12.
void merge_arrivals(std::vector<Arrival>& arrivals, double window_ps);

// Samples the expected waveform n(t_j)·Δt at t_j = j·Δt after emission. The shape is tabulated
// once on a grid of Δt/kSubSteps (by phase) and interpolated linearly, so a waveform costs a
// vectorised multiply-add per arrival and sample instead of an exponential.
class WaveformSynth {
  public:
    static constexpr std::size_t kSubSteps = 32;
    // ConfigError naming `source` unless 0 < sample_period_ns ≤ 1e3. The period need not be a
    // whole number of ps (3 GS/s: 333.3 ps): sample times are j·Δt in double, exact to far below
    // a ps over any gate.
    WaveformSynth(const sensor::PulseShape& shape, double sample_period_ns,
                  const std::string& source);

    double period_ns() const { return 1e-3 * period_ps_; }
    // Samples an arrival at `delay_ps` reaches: [first_sample, end_sample), the first
    // ceil((t_a + begin)/Δt) with begin rounded up to a whole ps, so the shape is (but for
    // rounding, clamped in add()) never read before its start.
    std::int64_t first_sample(std::int64_t delay_ps) const {
        return static_cast<std::int64_t>(std::ceil(double(delay_ps + begin_ps_) / period_ps_));
    }
    std::int64_t end_sample(std::int64_t delay_ps) const {
        return static_cast<std::int64_t>(std::floor(double(delay_ps + end_ps_) / period_ps_)) + 1;
    }
    // out[j − j0] += pe·s(t_j − t_a)·Δt for the samples of `out` (t in ns, s in 1/ns).
    void add(const Arrival& a, std::int64_t j0, std::span<double> out) const;

  private:
    static void accumulate(const double* __restrict s0, const double* __restrict s1, double f,
                           double pe, double* __restrict o, std::size_t n);
    void trim(const sensor::PulseShape& shape);

    double period_ps_ = 0;
    std::int64_t begin_ps_ = 0, end_ps_ = 0;
    double begin_ns_ = 0, end_ns_ = 0, step_ns_ = 0;
    std::size_t row_ = 0;        // entries per phase row
    std::vector<double> table_;  // (kSubSteps + 1) rows of s(begin + (p + kSubSteps·i)·step)·Δt
};

}  // namespace mirage::physics
