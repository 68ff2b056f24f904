// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/first_event.hpp"

#include <algorithm>
#include <cmath>

namespace mirage::physics {
namespace {

// Where Λ at a signal bin's end first exceeds the level: that bin k (−1: none does), its signal
// s, Λ's signal part before it (c_before) and the signal bin before it (−1: none).
struct Crossing {
    std::int64_t k = -1, before = -1;
    double s = 0, c_before = 0;
};

bool has_signal(const SignalRun& r, std::int64_t j) {
    const double s = r.scale * r.w[j];
    return s > 0.0 && s < EventRate::kHuge;  // as add_run takes a bin
}

// The bins of run r (from 0, up to hi) whose Λ at the end lies at or below the level, c the
// signal before the run: Λ never falls along a run (a bin without signal adds the noise), so
// they come first and their count is the first bin above the level.
std::int64_t bins_at_or_below(const SignalRun& r, std::int64_t hi, double noise, double c,
                              double level) {
    const double k1 = double(r.k0 + 1);
    std::int64_t count = 0;
    for (std::int64_t j = 0; j < hi; ++j)
        count += std::fma(noise, k1 + double(j), std::fma(r.scale, r.shares[j], c)) <= level;
    return count;
}

// The last bin of run r before `to` that has signal, or −1.
std::int64_t last_with_signal(const SignalRun& r, std::int64_t to) {
    for (std::int64_t j = to - 1; j >= 0; --j)
        if (has_signal(r, j)) return j;
    return -1;
}

// EventRate::time_at's formula for the level: inside bin x.k, in the noise before it, or (no
// crossing) in the noise after the last signal bin, c the signal of all bins; +inf: never.
double time_at_level(const Crossing& x, double c, std::size_t bins, double noise, double bin_ns,
                     double level) {
    if (x.k < 0) {
        if (!(level < std::fma(noise, double(bins), c)) || !(noise > 0.0)) return INFINITY;
        return std::min(double(bins), (level - c) / noise) * bin_ns;
    }
    if (const double start = std::fma(noise, double(x.k), x.c_before); level >= start)
        return (double(x.k) + std::min(1.0, (level - start) / (noise + x.s))) * bin_ns;
    if (noise > 0.0) return std::min(double(bins), (level - x.c_before) / noise) * bin_ns;
    return double(x.k) * bin_ns;
}

}  // namespace

// EventRate::add_run's sums (Λ's signal part at a bin: the sum before its run plus scale times
// the run's shares up to it; its end adds noise·(k + 1)), time_at's and signal_share's formulas
// on the one bin they read: the same doubles.
FirstEventResult gated_first_event(std::span<const SignalRun> runs, std::size_t bins,
                                   double noise_per_bin, double bin_ns, double level,
                                   double u_signal, GeigerEvent& out) {
    const double noise = noise_per_bin;
    std::int64_t last = -1;  // the last bin with signal
    double c = 0;            // the signal before the run
    Crossing x;
    for (const SignalRun& r : runs) {
        const std::int64_t hi =
            std::min<std::int64_t>(std::int64_t(r.n), std::int64_t(bins) - r.k0);
        if (r.k0 + std::int64_t(r.n) > 0 && std::max<std::int64_t>(r.k0, 0) <= last)
            return FirstEventResult::Undecided;  // overlaps: merged bin by bin
        const std::int64_t lo = std::max<std::int64_t>(0, -r.k0);
        if (lo >= hi) continue;                          // outside the gate
        if (lo > 0) return FirstEventResult::Undecided;  // its sums start inside the run
        if (x.k < 0) {
            std::int64_t j = bins_at_or_below(r, hi, noise, c, level);
            while (j < hi && !has_signal(r, j)) ++j;  // the first entry above: one with signal
            if (j < hi) {
                const std::int64_t before = last_with_signal(r, j);
                x = {r.k0 + j, before >= 0 ? r.k0 + before : last, r.scale * r.w[j],
                     j > 0 ? std::fma(r.scale, r.shares[j - 1], c) : c};
            }
        }
        if (const std::int64_t e = last_with_signal(r, hi); e >= 0) last = r.k0 + e;
        c = std::fma(r.scale, r.shares[hi - 1], c);
    }
    const double t = time_at_level(x, c, bins, noise, bin_ns, level);
    if (!(t < bin_ns * double(bins))) return FirstEventResult::None;  // (+inf: none)
    const auto bin = std::int64_t(std::min(bins - 1, static_cast<std::size_t>(t / bin_ns)));
    double n;  // the bin's expected primary events
    if (x.k >= 0 && bin == x.k)
        n = noise + x.s;
    else if (x.k >= 0 ? bin > x.before && bin < x.k : bin > last)
        n = noise;
    else
        return FirstEventResult::Undecided;
    const double share = n > 0.0 ? std::max(0.0, 1.0 - noise / n) : 0.0;
    out = {t, u_signal < share ? EventKind::Signal : EventKind::Noise};
    return FirstEventResult::Event;
}

}  // namespace mirage::physics
