// SPDX-License-Identifier: Apache-2.0
#include "mirage/sensor/pulse_shape.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "mirage/core/error.hpp"

namespace mirage::sensor {
namespace {

// 2·√(2 ln 2): FWHM of a Gaussian over its σ.
const double kFwhmPerSigma = 2.0 * std::sqrt(2.0 * std::numbers::ln2);
// A Gaussian is evaluated out to this many σ (its tail beyond weighs 6e-16).
constexpr double kGaussianSigmas = 8.0;

[[noreturn]] void fail(const std::string& source, const std::string& what) {
    throw ConfigError("pulse shape '" + source + "': " + what);
}

// ∫ t^k p(t) dt over a segment where p goes linearly from p0 at t0 to p1 at t0 + h (k = 0, 1, 2).
void add_moments(double t0, double h, double p0, double p1, double (&m)[3]) {
    const double d = p1 - p0;
    const double a = p0 + d / 2, b = p0 / 2 + d / 3, c = p0 / 3 + d / 4;  // ∫u^j (p0 + d·u) du
    m[0] += h * a;
    m[1] += h * (t0 * a + h * b);
    m[2] += h * (t0 * t0 * a + 2 * t0 * h * b + h * h * c);
}

// Width at half the peak of a piecewise-linear shape: the outermost half-peak crossings.
double tabulated_fwhm(const std::vector<double>& t, const std::vector<double>& p) {
    const double half = *std::max_element(p.begin(), p.end()) / 2;
    // Where the segment from sample i (at or above `half`) to its neighbour j (below) meets
    // `half`, measured from i: the step is a fraction of the segment in [0, 1], so the crossing
    // stays on i's side of the segment even when j lies astronomically far (found by
    // fuzz_pulse_table: measured from j, 2 − 1.1e84 + 1.1e84 rounded to 0) and hi ≥ lo.
    auto step = [&](std::size_t i, std::size_t j) {
        return std::abs(t[j] - t[i]) * ((p[i] - half) / (p[i] - p[j]));
    };
    std::size_t first = 0, last = p.size() - 1;
    while (p[first] < half) ++first;
    while (p[last] < half) --last;
    const double lo = first == 0 ? t[0] : t[first] - step(first, first - 1);
    const double hi = last + 1 == p.size() ? t[last] : t[last] + step(last, last + 1);
    return hi - lo;
}

}  // namespace

PulseShape PulseShape::gaussian(double fwhm_ns, const std::string& source) {
    if (!(fwhm_ns > 0 && std::isfinite(fwhm_ns)))
        fail(source, "fwhm_ns must be a positive number of ns");
    PulseShape s;
    s.fwhm_ns_ = fwhm_ns;
    s.sigma_ns_ = fwhm_ns / kFwhmPerSigma;
    s.begin_ns_ = -kGaussianSigmas * s.sigma_ns_;
    s.end_ns_ = kGaussianSigmas * s.sigma_ns_;
    return s;
}

PulseShape PulseShape::tabulated(std::vector<double> t, std::vector<double> p,
                                 const std::string& source) {
    if (t.size() < 2 || t.size() != p.size())
        fail(source, "needs at least 2 samples, one power per time");
    for (std::size_t i = 0; i < t.size(); ++i) {
        if (!std::isfinite(t[i]) || (i > 0 && !(t[i] > t[i - 1])))
            fail(source, "sample " + std::to_string(i) + ": times must increase strictly");
        if (!(p[i] >= 0 && std::isfinite(p[i])))
            fail(source, "sample " + std::to_string(i) + ": power must be finite and >= 0");
    }
    double m[3] = {0, 0, 0};
    for (std::size_t i = 1; i < t.size(); ++i)
        add_moments(t[i - 1], t[i] - t[i - 1], p[i - 1], p[i], m);
    if (!(m[0] > 0)) fail(source, "the shape has no area");
    // Times or powers so large that the moments overflow (found by fuzz_pulse_table).
    if (!std::isfinite(m[0]) || !std::isfinite(m[1]) || !std::isfinite(m[2]) ||
        !std::isfinite(m[2] / m[0] - (m[1] / m[0]) * (m[1] / m[0])))
        fail(source, "the shape's moments overflow a double");
    const double centroid = m[1] / m[0];
    PulseShape s;
    s.sigma_ns_ = std::sqrt(std::max(0.0, m[2] / m[0] - centroid * centroid));
    s.fwhm_ns_ = tabulated_fwhm(t, p);
    for (double& x : t) x -= centroid;
    for (double& x : p) x /= m[0];
    s.begin_ns_ = t.front();
    s.end_ns_ = t.back();
    s.t_ = std::move(t);
    s.p_ = std::move(p);
    return s;
}

double PulseShape::operator()(double t_ns) const {
    if (!(t_ns >= begin_ns_ && t_ns <= end_ns_)) return 0.0;
    if (t_.empty()) {
        const double z = t_ns / sigma_ns_;
        return std::exp(-0.5 * z * z) / (sigma_ns_ * std::sqrt(2 * std::numbers::pi));
    }
    const auto j =
        static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), t_ns) - t_.begin());
    if (j >= t_.size()) return p_.back();
    const double u = (t_ns - t_[j - 1]) / (t_[j] - t_[j - 1]);
    return p_[j - 1] + u * (p_[j] - p_[j - 1]);
}

}  // namespace mirage::sensor
