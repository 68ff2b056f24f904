// SPDX-License-Identifier: Apache-2.0
// Gaussian decomposition of a digitised waveform (docs/time-resolved.md §12): the waveform as a
// sum of Gaussians fitted by least squares, components added where the residual holds an echo.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "mirage/physics/linear_detector.hpp"

namespace mirage::physics {
namespace {

struct Component {
    double a = 0, t = 0, s = 1;  // amplitude (counts above the baseline), centre, width (samples)
};

struct Samples {
    std::vector<double> y, w;  // above the baseline; weight 1/variance
};

double model_at(const std::vector<Component>& c, double j) {
    double m = 0;
    for (const Component& k : c) {
        const double u = (j - k.t) / k.s;
        m += k.a * std::exp(-0.5 * u * u);
    }
    return m;
}

double chi2(const Samples& v, const std::vector<Component>& c) {
    double sum = 0;
    for (std::size_t j = 0; j < v.y.size(); ++j) {
        const double r = v.y[j] - model_at(c, double(j));
        sum += v.w[j] * r * r;
    }
    return sum;
}

// The Gaussian model's own error, relative to a sample: a stretched echo (a tilted surface) is a
// sum of pulses, Gaussian only approximately, and at high signal-to-noise χ² would otherwise
// split it.
constexpr double kModelError = 0.01;
// Without noise, the error a sample may keep: 1 % of the highest (equal echoes then separate
// from 1.6σ_p, where the sum has one maximum below 2σ_p, and an echo stretched by up to σ_p stays
// one component).
constexpr double kNoiseFreeTolerance = 0.01;

// At most this many components per fit (kMaxParams parameters): the matrices stay on the stack.
constexpr std::size_t kMaxComponents = 8;
constexpr int kMaxParams = 3 * int(kMaxComponents);
using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxParams, kMaxParams>;
using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxParams, 1>;

// The normal equations JᵀWJ and JᵀWr of the model at `c` (parameters a, t, s per component).
void normal_equations(const Samples& v, const std::vector<Component>& c, Matrix& a, Vector& g) {
    const std::size_t np = 3 * c.size();
    a.setZero(Eigen::Index(np), Eigen::Index(np));
    g.setZero(Eigen::Index(np));
    double row[kMaxParams];
    for (std::size_t j = 0; j < v.y.size(); ++j) {
        double m = 0;
        for (std::size_t k = 0; k < c.size(); ++k) {
            const double d = double(j) - c[k].t, u = d / c[k].s, e = std::exp(-0.5 * u * u);
            row[3 * k] = e;
            row[3 * k + 1] = c[k].a * e * d / (c[k].s * c[k].s);
            row[3 * k + 2] = row[3 * k + 1] * d / c[k].s;
            m += c[k].a * e;
        }
        const double w = v.w[j], wr = w * (v.y[j] - m);
        for (std::size_t p = 0; p < np; ++p) {
            const double wp = w * row[p];
            for (std::size_t q = 0; q <= p; ++q) a(Eigen::Index(p), Eigen::Index(q)) += wp * row[q];
            g[Eigen::Index(p)] += wr * row[p];
        }
    }
    a.triangularView<Eigen::StrictlyUpper>() = a.transpose();
}

// Parameters at a bound that the gradient pushes past it are held (their row and column of the
// normal equations cleared): a clamped step would otherwise promise a gain it cannot make.
void hold_bounds(const std::vector<Component>& c, double s_min, double n, Matrix& a, Vector& g) {
    const auto hold = [&](Eigen::Index i) {
        a.row(i).setZero();
        a.col(i).setZero();
        a(i, i) = 1;
        g[i] = 0;
    };
    for (std::size_t k = 0; k < c.size(); ++k) {
        const auto i = Eigen::Index(3 * k);
        if (c[k].a <= 0 && g[i] < 0) hold(i);
        if ((c[k].t <= 0 && g[i + 1] < 0) || (c[k].t >= n - 1 && g[i + 1] > 0)) hold(i + 1);
        if ((c[k].s <= s_min && g[i + 2] < 0) || (c[k].s >= n && g[i + 2] > 0)) hold(i + 2);
    }
}

// Levenberg–Marquardt on `c`, widths kept ≥ s_min, centres inside the samples, amplitudes ≥ 0.
void fit_sum(const Samples& v, std::vector<Component>& c, double s_min) {
    const double n = double(v.y.size());
    double lambda = 1e-3, cur = chi2(v, c);
    Matrix a, m;
    Vector g;
    for (int it = 0; it < 100 && std::isfinite(cur); ++it) {
        normal_equations(v, c, a, g);
        hold_bounds(c, s_min, n, a, g);
        bool better = false, converged = false;
        double next = cur;
        for (int tries = 0; tries < 12 && !better; ++tries) {
            m = a;
            m.diagonal() *= 1 + lambda;
            m.diagonal().array() += 1e-12;
            const Vector step = m.ldlt().solve(g);
            // The step's predicted gain in χ² (gᵀδ for a Gauss–Newton step): below 10⁻³ the fit
            // has converged, and no damping would find more.
            if (!(step.dot(g) > 1e-3)) {
                converged = true;
                break;
            }
            std::vector<Component> trial = c;
            for (std::size_t k = 0; k < c.size(); ++k) {
                const auto i = static_cast<Eigen::Index>(3 * k);
                trial[k].a = std::max(0.0, c[k].a + step[i]);
                trial[k].t = std::clamp(c[k].t + step[i + 1], 0.0, n - 1);
                trial[k].s = std::clamp(c[k].s + step[i + 2], s_min, n);
            }
            next = chi2(v, trial);
            if (next < cur) {
                c = std::move(trial);
                lambda = std::max(lambda * 0.1, 1e-12);
                better = true;
            } else {
                lambda *= 10;
            }
        }
        // χ² is in units of the noise: a gain of 10⁻³ (or 10⁻⁹ of it) changes no decision.
        if (converged || !better || cur - next <= 1e-3 + 1e-9 * cur) break;
        cur = next;
    }
}

// Drops components below `thr`; true if any went.
bool drop_weak(std::vector<Component>& c, double thr) {
    const auto before = c.size();
    std::erase_if(c, [&](const Component& k) { return !(k.a >= thr); });
    return c.size() != before;
}

// The sample whose residual, in units of its noise, is the largest positive one; n if none is.
std::size_t most_unexplained(const Samples& v, const std::vector<Component>& c) {
    std::size_t best = v.y.size();
    double most = 0;
    for (std::size_t j = 0; j < v.y.size(); ++j) {
        const double r = (v.y[j] - model_at(c, double(j))) * std::sqrt(v.w[j]);
        if (r > most) {
            most = r;
            best = j;
        }
    }
    return best;
}

// `c` with one more component for the residual at sample j, fitted: from three starts (a new
// component at j; the nearest component split in two about its centre; that one kept, shifted
// away from j, and a new one at j), the one of least χ² after weak components are dropped.
std::vector<Component> with_one_more(const Samples& v, const std::vector<Component>& c,
                                     std::size_t j, double s_min, double thr) {
    const double x = double(j);
    std::vector<std::vector<Component>> starts(1, c);
    starts[0].push_back({std::max(thr, v.y[j] - model_at(c, x)), x, s_min});
    const auto near = std::min_element(c.begin(), c.end(), [&](const auto& a, const auto& b) {
        return std::abs(a.t - x) < std::abs(b.t - x);
    });
    if (near != c.end()) {
        const auto k = static_cast<std::size_t>(near - c.begin());
        const double d = std::max(std::abs(near->t - x), 0.5 * s_min);
        const double dir = x >= near->t ? 1.0 : -1.0, s = std::max(s_min, 0.8 * near->s);
        starts.push_back(c);
        starts.back()[k] = {0.5 * near->a, near->t - dir * d, s};
        starts.back().push_back({0.5 * near->a, near->t + dir * d, s});
        starts.push_back(c);
        starts.back()[k] = {0.8 * near->a, near->t - 0.5 * dir * d, s};
        starts.back().push_back({0.4 * near->a, x + 0.5 * dir * d, s});
    }
    std::vector<Component> best;
    double best_chi = INFINITY;
    for (auto& t : starts) {
        fit_sum(v, t, s_min);
        drop_weak(t, thr);
        const double chi = chi2(v, t);
        if (t.size() > c.size() && chi < best_chi) {
            best_chi = chi;
            best = std::move(t);
        }
    }
    return best;
}

// The samples above the baseline `off` and their weights: 1/(variance of the sample's noise +
// the model's own error, kModelError of the sample: a stretched echo is a Gaussian only
// approximately); without noise a floor of kNoiseFreeTolerance of the highest sample instead of
// the noise. A clipped sample says only that the signal was at least full scale: weight 0
// (noise-free counts are not clipped).
Samples weighed(const LinearDetector& d, const double* counts, std::size_t n, double off,
                double floor_pe, bool noisy) {
    const double g = d.params().gain_counts_per_pe, full = std::ldexp(1.0, d.params().bits) - 1;
    Samples v;
    for (std::size_t j = 0; j < n; ++j) v.y.push_back(counts[j] - off);
    const double tol =
        kNoiseFreeTolerance * std::max(1.0, *std::max_element(v.y.begin(), v.y.end()));
    for (std::size_t j = 0; j < n; ++j) {
        const double y = v.y[j], sd = d.sigma_counts(std::max(0.0, y) / g + floor_pe);
        const double var =
            (noisy ? sd * sd + 1.0 / 12.0 : tol * tol) + kModelError * kModelError * y * y;
        const bool clipped = noisy && (counts[j] >= full || counts[j] <= 0);
        v.w.push_back(clipped ? 0.0 : 1.0 / var);
    }
    return v;
}

// Components added one at a time where the residual is largest, each kept when all stay above
// the threshold and χ² falls by more than kAddChi2 (three more parameters; ~5σ); at most `max`.
void add_components(const Samples& v, std::vector<Component>& c, double s_min, double thr,
                    std::size_t max) {
    constexpr double kAddChi2 = 25.0;
    // A clipped waveform leaves its top unknown: any number of Gaussians fit there.
    if (std::any_of(v.w.begin(), v.w.end(), [](double w) { return w == 0; })) return;
    double chi = chi2(v, c);
    while (c.size() < max) {
        // A fit that explains the samples leaves χ² near its degrees of freedom; one more
        // component can only gain kAddChi2 where χ² stands well above them.
        const double dof = double(v.y.size()) - 3.0 * double(c.size());
        if (chi < kAddChi2 || chi - dof < 0.5 * kAddChi2) return;
        const std::size_t j = most_unexplained(v, c);
        if (j == v.y.size()) return;
        std::vector<Component> more = with_one_more(v, c, j, s_min, thr);
        if (more.empty()) return;  // no start kept a new component: the residual is no echo
        const double chi_more = chi2(v, more);
        if (!(chi - chi_more > kAddChi2)) return;
        c = std::move(more);
        chi = chi_more;
    }
}

// The components, in time order, as echoes from sample j0 on a clock of `period` ns: photo-
// electrons A·s·√(2π)/g, deviation the fit's RMS residual over t ± 3s.
void write_echoes(const Samples& v, std::vector<Component>& c, std::int64_t j0, double period,
                  double g, Echo* out) {
    std::sort(c.begin(), c.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
    const double n = double(v.y.size()), root_2pi = std::sqrt(2 * std::numbers::pi);
    for (std::size_t k = 0; k < c.size(); ++k) {
        Echo& e = out[k];
        e = Echo{};
        e.time_ns = (double(j0) + c[k].t) * period;
        e.amplitude_counts = c[k].a;
        e.sigma_ns = c[k].s * period;
        e.pe = c[k].a * c[k].s * root_2pi / g;
        const auto lo =
            static_cast<std::size_t>(std::clamp(std::floor(c[k].t - 3 * c[k].s), 0.0, n - 1));
        const auto hi = static_cast<std::size_t>(
            std::clamp(std::ceil(c[k].t + 3 * c[k].s) + 1, double(lo + 1), n));
        double sum = 0;
        for (std::size_t j = lo; j < hi; ++j) {
            const double r = v.y[j] - model_at(c, double(j));
            sum += r * r;
        }
        e.deviation = std::sqrt(sum / double(hi - lo));
        e.first = j0 + static_cast<std::int64_t>(lo);
        e.end = j0 + static_cast<std::int64_t>(hi);
    }
}

}  // namespace

std::size_t LinearDetector::decompose(const double* counts, std::size_t n, std::int64_t j0,
                                      double floor_pe, bool noisy, double min_sigma_ns,
                                      Echo* echoes, std::size_t found, std::size_t max) const {
    if (found == 0 || n == 0 || max == 0) return 0;
    if (found > kMaxComponents) return found;  // a busy waveform keeps its peak-timed echoes
    const double g = p_.gain_counts_per_pe, off = p_.offset_counts + g * floor_pe;
    const double thr = threshold(floor_pe), s_min = std::max(0.3, min_sigma_ns / period_ns_);
    const Samples v = weighed(*this, counts, n, off, floor_pe, noisy);
    std::vector<Component> c;
    for (std::size_t e = 0; e < found; ++e)
        c.push_back({echoes[e].amplitude_counts,
                     std::clamp(echoes[e].time_ns / period_ns_ - double(j0), 0.0, double(n - 1)),
                     std::max(s_min, echoes[e].sigma_ns / period_ns_)});
    fit_sum(v, c, s_min);
    // The seeds crossed the threshold already: one goes only when its neighbours took it over.
    if (drop_weak(c, 0.5 * thr) && !c.empty()) fit_sum(v, c, s_min);
    add_components(v, c, s_min, thr, std::min(max, kMaxComponents));
    write_echoes(v, c, j0, period_ns_, g, echoes);
    return c.size();
}

}  // namespace mirage::physics
