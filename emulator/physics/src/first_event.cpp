// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/first_event.hpp"

#include <algorithm>
#include <cmath>

namespace mirage::physics {
namespace {

constexpr double kHuge = 1e300;  // as EventRate: a signal above it is taken as not finite

// Where the running sum Λ crossed the level: the bin k holding signal s, Λ's signal part before
// it (c_before) and the signal bin before it (−1: none). Past every signal bin: k = −1.
struct Crossing {
    std::int64_t k = -1, before = -1;
    double s = 0, c_before = 0;
};

bool has_signal(const SignalRun& r, std::int64_t j) {
    const double s = r.scale * r.w[j];
    return s > 0.0 && s < kHuge;
}

}  // namespace

// EventRate::add_run's sums in its order (c += s; end = noise·(k + 1) + c) up to the bin where
// Λ crosses the level, time_at's and signal_share's formulas on the one bin they read: the same
// doubles. Past the crossing no sum is needed (the total lies above the level), only each run's
// last bin with signal, for the overlap test.
FirstEventResult gated_first_event(std::span<const SignalRun> runs, std::size_t bins,
                                   double noise_per_bin, double bin_ns, double level,
                                   double u_signal, GeigerEvent& out) {
    const double noise = noise_per_bin;
    std::int64_t last = -1;  // the last bin with signal
    double c = 0;
    Crossing x;
    bool crossed = false;
    for (const SignalRun& r : runs) {
        const std::int64_t lo = std::max<std::int64_t>(0, -r.k0);
        const std::int64_t hi =
            std::min<std::int64_t>(std::int64_t(r.n), std::int64_t(bins) - r.k0);
        if (r.k0 + std::int64_t(r.n) > 0 && std::max<std::int64_t>(r.k0, 0) <= last)
            return FirstEventResult::Undecided;  // overlaps: merged bin by bin
        std::int64_t j = lo;
        for (; j < hi && !crossed; ++j) {
            const double s = r.scale * r.w[j];
            if (!(s > 0.0) || !(s < kHuge)) continue;
            const std::int64_t k = r.k0 + j;
            const double before = c;
            c += s;
            if (noise * double(static_cast<std::uint32_t>(k + 1)) + c > level) {
                x = {k, last, s, before};
                crossed = true;
            }
            last = k;
        }
        if (!crossed) continue;
        for (std::int64_t e = hi - 1; e >= j; --e)
            if (has_signal(r, e)) {
                last = r.k0 + e;
                break;
            }
    }
    if (!crossed && !(level < noise * double(bins) + c))
        return FirstEventResult::None;  // beyond the gate
    double t;
    if (!crossed) {  // in the noise after the last signal bin
        if (!(noise > 0.0)) return FirstEventResult::None;  // (at the gate's end)
        t = std::min(double(bins), (level - c) / noise) * bin_ns;
    } else if (const double start = noise * double(x.k) + x.c_before; level >= start) {
        t = (double(x.k) + std::min(1.0, (level - start) / (noise + x.s))) * bin_ns;
    } else if (noise > 0.0) {  // in the noise before bin k
        t = std::min(double(bins), (level - x.c_before) / noise) * bin_ns;
    } else {
        t = double(x.k) * bin_ns;
    }
    if (!(t < bin_ns * double(bins))) return FirstEventResult::None;
    const auto bin = std::int64_t(std::min(bins - 1, static_cast<std::size_t>(t / bin_ns)));
    double n;  // the bin's expected primary events
    if (crossed && bin == x.k)
        n = noise + x.s;
    else if (crossed ? bin > x.before && bin < x.k : bin > last)
        n = noise;
    else
        return FirstEventResult::Undecided;
    const double share = n > 0.0 ? std::max(0.0, 1.0 - noise / n) : 0.0;
    out = {t, u_signal < share ? EventKind::Signal : EventKind::Noise};
    return FirstEventResult::Event;
}

}  // namespace mirage::physics
