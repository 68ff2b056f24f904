// SPDX-License-Identifier: Apache-2.0
// Linear-mode APD receiver with a waveform digitiser (docs/time-resolved.md §7, physics.md §5):
// expected photo-electrons per sample -> digitised counts -> echoes with time, amplitude, width.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "mirage/sensor/sensor.hpp"

namespace mirage::physics {

using sensor::LinearDetectorParams;

// One echo found in a digitised waveform.
struct Echo {
    double time_ns = 0;           // fitted peak, after emission
    double amplitude_counts = 0;  // fitted peak above the baseline
    double sigma_ns = 0;          // fitted Gaussian width (RMS)
    double pe = 0;                // photo-electrons of the echo (its samples above the baseline)
    double deviation = 0;  // RMS of its samples about the fitted Gaussian (set by the caller)
    std::int64_t first = 0, end = 0;  // its samples: from the valley before to the one after
    std::uint32_t tag = 0;            // the caller's own (the renderer: its deviation's job)
};

class LinearDetector {
  public:
    // ConfigError naming `source` and the key for impossible values (bits outside 1–32, gains
    // ≤ 0, k outside [0, 1], negative noise, a threshold beyond full scale).
    LinearDetector(const LinearDetectorParams& p, const std::string& source);

    const LinearDetectorParams& params() const { return p_; }
    // F = k·M + (1 − k)(2 − 1/M) (McIntyre).
    double excess_noise() const { return excess_; }
    // Primary dark electrons per ns.
    double dark_rate_per_ns() const { return dark_per_ns_; }
    // Noise of a sample expecting n primary photo-electrons, in counts: g·√(F·n + σ_th²).
    double sigma_counts(double n_pe) const;
    // The threshold above the offset for a noise floor of `floor_pe` per sample.
    double threshold(double floor_pe) const;

    // counts[j] = clamp(offset + g·(n[j] + √(F·n[j] + σ_th²)·z[j]), 0, full scale), rounded to
    // whole counts. z null: the noise-free limit (no noise, no rounding, no clipping).
    void digitise(const double* n_pe, const double* z, std::size_t n, double* counts) const;
    // Echoes of counts[0, n) (sample j0 + j at (j0 + j)·Δt) in time order, at most `max`,
    // measured from the baseline offset + g·floor_pe (floor_pe: expected background and dark
    // photo-electrons per sample): maxima above the threshold, two of them separate when the signal
    // between them dips below the lower by 3σ of its noise (any dip when `noisy` is false); each
    // fitted by a Gaussian through its sample and its neighbours (time, amplitude, width); its
    // photo-electrons are the sum of its samples between the valleys around it. Returns how many (≤
    // 32).
    std::size_t find_echoes(const double* counts, std::size_t n, std::int64_t j0, double floor_pe,
                            bool noisy, Echo* out, std::size_t max) const;

    // Constant-fraction timing of echo `e` (from find_echoes on the same counts, baseline in
    // counts): when the signal first rises through `fraction` of its amplitude before its highest
    // sample, ln y interpolated by the parabola through the samples around the crossing (exact
    // for a Gaussian edge), linearly where one of them is not above the baseline. Add the pulse's
    // own crossing-to-centroid delay for a range (docs/time-resolved.md §12).
    double leading_edge_ns(const double* counts, std::size_t n, std::int64_t j0, double baseline,
                           const Echo& e, double fraction) const;
    // Gaussian decomposition of counts[0, n) (docs/time-resolved.md §12): echoes[0, found) from
    // find_echoes seed a least-squares fit (Levenberg–Marquardt, weighted by each sample's noise
    // when `noisy`) of a sum of Gaussians no narrower than `min_sigma_ns`; a component is added
    // where the residual exceeds the threshold and 4σ of the sample's noise, and dropped when its
    // amplitude falls below the threshold. Replaces echoes[0, ·) in time order, deviation set to
    // the RMS residual over each component's samples; returns how many (≤ max).
    std::size_t decompose(const double* counts, std::size_t n, std::int64_t j0, double floor_pe,
                          bool noisy, double min_sigma_ns, Echo* echoes, std::size_t found,
                          std::size_t max) const;

  private:
    static constexpr std::size_t kMaxPeaks = 32;
    std::size_t peaks(const double* counts, std::size_t n, double baseline, double thr, bool noisy,
                      std::size_t* out, std::size_t max) const;
    Echo fit(const double* counts, std::size_t n, std::size_t j, std::int64_t j0,
             double baseline) const;

    LinearDetectorParams p_;
    double excess_ = 1, dark_per_ns_ = 0, full_scale_ = 0, period_ns_ = 1;
};

}  // namespace mirage::physics
