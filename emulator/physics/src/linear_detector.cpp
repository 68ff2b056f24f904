// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/linear_detector.hpp"

#include <algorithm>
#include <cmath>

#include "mirage/core/error.hpp"

namespace mirage::physics {
namespace {

constexpr double kElectronChargeC = 1.602176634e-19;

void require(bool ok, const std::string& source, const char* key, const std::string& what) {
    if (!ok) throw ConfigError(source + ": detector." + key + ": " + what);
}

}  // namespace

LinearDetector::LinearDetector(const LinearDetectorParams& p, const std::string& source) : p_(p) {
    require(p.sample_rate_gsps > 0 && p.sample_rate_gsps <= 100, source, "sample_rate_gsps",
            "must be in (0, 100]");
    require(p.bits >= 1 && p.bits <= 32, source, "bits", "must be 1–32");
    full_scale_ = std::ldexp(1.0, p.bits) - 1.0;
    require(p.offset_counts >= 0 && p.offset_counts < full_scale_, source, "offset_counts",
            "must be in [0, full scale)");
    require(p.gain_counts_per_pe > 0 && std::isfinite(p.gain_counts_per_pe), source,
            "gain_counts_per_pe", "must be > 0");
    require(p.apd_gain >= 1 && p.apd_gain <= 1e4, source, "apd_gain", "must be in [1, 1e4]");
    require(p.apd_k >= 0 && p.apd_k <= 1, source, "apd_k", "must be in [0, 1]");
    require(p.thermal_noise_pe >= 0 && std::isfinite(p.thermal_noise_pe), source,
            "thermal_noise_pe", "must be ≥ 0");
    require(p.dark_current_na >= 0 && p.dark_current_na <= 1e6, source, "dark_current_na",
            "must be in [0, 1e6]");
    require(p.threshold_counts >= 0 && p.threshold_counts < full_scale_ - p.offset_counts, source,
            "threshold_counts", "must be ≥ 0 and below full scale minus the offset");
    const double m = p.apd_gain;
    excess_ = p.apd_k * m + (1 - p.apd_k) * (2 - 1 / m);
    dark_per_ns_ = p.dark_current_na * 1e-9 / kElectronChargeC * 1e-9;
    period_ns_ = 1.0 / p.sample_rate_gsps;
}

double LinearDetector::sigma_counts(double n_pe) const {
    const double th = p_.thermal_noise_pe;
    return p_.gain_counts_per_pe * std::sqrt(excess_ * std::max(0.0, n_pe) + th * th);
}

double LinearDetector::threshold(double floor_pe) const {
    if (p_.threshold_counts > 0) return p_.threshold_counts;
    return std::max(1.0, 4.0 * sigma_counts(floor_pe));
}

void LinearDetector::digitise(const double* n_pe, const double* z, std::size_t n,
                              double* counts) const {
    const double g = p_.gain_counts_per_pe, off = p_.offset_counts;
    if (!z) {
        for (std::size_t j = 0; j < n; ++j) counts[j] = off + g * n_pe[j];
        return;
    }
    // Members in locals and restrict pointers: `counts` could otherwise alias *this, and every
    // sample would reload them in a scalar loop.
    const double excess = excess_, th2 = p_.thermal_noise_pe * p_.thermal_noise_pe;
    const double top = full_scale_;
    const double* __restrict in = n_pe;
    const double* __restrict zz = z;
    double* __restrict out = counts;
    for (std::size_t j = 0; j < n; ++j) {
        const double sigma = g * std::sqrt(excess * std::max(0.0, in[j]) + th2);  // sigma_counts
        out[j] = std::clamp(std::nearbyint(off + g * in[j] + sigma * zz[j]), 0.0, top);
    }
}

// Three-point Gaussian fit: ln y is a parabola through samples j − 1, j, j + 1. Where a
// neighbour is missing or not above the offset (or ln y is not concave), the sample itself,
// width 0 (not measured).
Echo LinearDetector::fit(const double* counts, std::size_t n, std::size_t j, std::int64_t j0,
                         double off) const {
    const double y0 = counts[j] - off;
    const double ym = j > 0 ? counts[j - 1] - off : 0.0;
    const double yp = j + 1 < n ? counts[j + 1] - off : 0.0;
    Echo e;
    double x = 0, sigma = 0, peak = y0;
    if (ym > 0 && yp > 0 && y0 > 0) {
        const double lm = std::log(ym), l0 = std::log(y0), lp = std::log(yp);
        const double a = 0.5 * (lm - 2 * l0 + lp), b = 0.5 * (lp - lm);
        if (a < 0) {
            x = std::clamp(-b / (2 * a), -0.5, 0.5);
            sigma = std::sqrt(-1 / (2 * a));
            peak = std::exp(l0 + b * x + a * x * x);
        }
    }
    e.time_ns = (static_cast<double>(j0 + static_cast<std::int64_t>(j)) + x) * period_ns_;
    e.amplitude_counts = peak;
    e.sigma_ns = sigma * period_ns_;
    return e;
}

// The maxima that make echoes, as sample indices in time order (at most `max`).
std::size_t LinearDetector::peaks(const double* counts, std::size_t n, double off, double thr,
                                  bool noisy, std::size_t* out, std::size_t max) const {
    const double g = p_.gain_counts_per_pe;
    std::size_t found = 0;
    std::size_t cur = n;  // the maximum being grown, n for none
    double valley = 0;    // the lowest sample since it
    for (std::size_t j = 0; j < n && found < max; ++j) {
        const double y = counts[j] - off;
        if (cur != n) valley = std::min(valley, y);
        const bool is_max = y > thr && (j == 0 || counts[j] > counts[j - 1]) &&
                            (j + 1 == n || counts[j] >= counts[j + 1]);
        if (!is_max) continue;
        if (cur == n) {
            cur = j;
            valley = y;
            continue;
        }
        const double lower = std::min(counts[cur] - off, y);
        const double margin = noisy ? 3 * sigma_counts(lower / g) : 0.0;
        if (valley < lower - margin || valley <= thr) {
            out[found++] = cur;
            cur = j;
        } else if (y > counts[cur] - off) {
            cur = j;
        }
        valley = y;
    }
    if (cur != n && found < max) out[found++] = cur;
    return found;
}

std::size_t LinearDetector::find_echoes(const double* counts, std::size_t n, std::int64_t j0,
                                        double floor_pe, bool noisy, Echo* out,
                                        std::size_t max) const {
    // The baseline: the offset plus the expected floor (a receiver tracks it between pulses).
    const double g = p_.gain_counts_per_pe, off = p_.offset_counts + g * floor_pe;
    std::size_t at[kMaxPeaks];
    const std::size_t found = peaks(counts, n, off, threshold(floor_pe), noisy, at,
                                    std::min<std::size_t>(max, kMaxPeaks));
    // Each echo's photo-electrons: the samples above the baseline from the lowest sample before
    // it to the lowest after it (exact for one echo of any shape, where a fit is not).
    auto lowest = [&](std::size_t a, std::size_t b) {
        return static_cast<std::size_t>(std::min_element(counts + a, counts + b) - counts);
    };
    std::size_t lo = 0;
    for (std::size_t e = 0; e < found; ++e) {
        const std::size_t hi = e + 1 < found ? lowest(at[e], at[e + 1]) : n;
        out[e] = fit(counts, n, at[e], j0, off);
        double sum = 0;
        for (std::size_t j = lo; j < hi; ++j) sum += counts[j] - off;
        out[e].pe = sum / g;
        out[e].first = j0 + static_cast<std::int64_t>(lo);
        out[e].end = j0 + static_cast<std::int64_t>(hi);
        lo = hi;
    }
    return found;
}

namespace {

// x in [−1, 0] where the parabola through (−1, lm), (0, l0), (1, lp) equals `level` on its
// rising side; NaN if it does not there.
double parabola_crossing(double lm, double l0, double lp, double level) {
    const double a = 0.5 * (lm - 2 * l0 + lp), b = 0.5 * (lp - lm), c = l0 - level;
    if (std::abs(a) < 1e-12 * (std::abs(b) + std::abs(c))) {
        const double x = b != 0 ? -c / b : NAN;
        return x >= -1 && x <= 0 ? x : NAN;
    }
    const double disc = b * b - 4 * a * c;
    if (disc < 0) return NAN;
    const double r = std::sqrt(disc);
    for (const double x : {(-b - r) / (2 * a), (-b + r) / (2 * a)})
        if (x >= -1 && x <= 0 && 2 * a * x + b > 0) return x;
    return NAN;
}

}  // namespace

double LinearDetector::leading_edge_ns(const double* counts, std::size_t n, std::int64_t j0,
                                       double off, const Echo& e, double fraction) const {
    const auto clip = [&](std::int64_t j) {
        return static_cast<std::size_t>(std::clamp<std::int64_t>(j - j0, 0, std::int64_t(n)));
    };
    const std::size_t lo = clip(e.first), hi = clip(e.end);
    if (lo >= hi) return NAN;
    const auto top = static_cast<std::size_t>(std::max_element(counts + lo, counts + hi) - counts);
    const double level = fraction * e.amplitude_counts;
    std::size_t j = top;
    while (j > lo && counts[j - 1] - off >= level) --j;
    // No sample below the level before the top inside the echo (it rides on an earlier one), or
    // the amplitude above every sample: no edge to time.
    if (j == 0 || counts[j] - off < level || counts[j - 1] - off >= level) return NAN;
    const double y1 = counts[j - 1] - off, y2 = counts[j] - off;
    double x = (level - y1) / (y2 - y1) - 1.0;  // linear, relative to sample j
    if (y1 > 0 && j + 1 < n && counts[j + 1] - off > 0) {
        const double xp = parabola_crossing(std::log(y1), std::log(y2),
                                            std::log(counts[j + 1] - off), std::log(level));
        if (!std::isnan(xp)) x = xp;
    }
    return (static_cast<double>(j0 + static_cast<std::int64_t>(j)) + x) * period_ns_;
}

}  // namespace mirage::physics
