// SPDX-License-Identifier: Apache-2.0
#include "mirage/physics/waveform.hpp"

#include <algorithm>
#include <cmath>

#include "mirage/core/error.hpp"

namespace mirage::physics {

WaveformSynth::WaveformSynth(const PulseShape& shape, double sample_period_ns,
                             const std::string& source) {
    const double ps = sample_period_ns * 1e3;
    if (!(sample_period_ns > 0 && sample_period_ns <= 1e3) || std::abs(ps - std::round(ps)) > 1e-6)
        throw ConfigError(source + ": the sample period " + std::to_string(sample_period_ns) +
                          " ns must be a whole number of ps in (0, 1000] ns");
    period_ps_ = static_cast<std::int64_t>(std::llround(ps));
    begin_ns_ = shape.begin_ns();
    end_ns_ = shape.end_ns();
    step_ns_ = period_ns() / kSubSteps;
    const auto m = static_cast<std::size_t>(std::ceil((end_ns_ - begin_ns_) / step_ns_)) + 1;
    table_.resize(m + 1, 0.0);
    for (std::size_t i = 0; i < m; ++i)
        table_[i] = shape(begin_ns_ + static_cast<double>(i) * step_ns_) * period_ns();
}

// First j with t_j − t_a ≥ begin: ceil((t_a + begin)/Δt), in integer ps.
std::int64_t WaveformSynth::first_sample(std::int64_t delay_ps) const {
    const auto lo = delay_ps + static_cast<std::int64_t>(std::floor(begin_ns_ * 1e3));
    return lo >= 0 ? (lo + period_ps_ - 1) / period_ps_ : -((-lo) / period_ps_);
}

std::int64_t WaveformSynth::end_sample(std::int64_t delay_ps) const {
    const auto hi = delay_ps + static_cast<std::int64_t>(std::ceil(end_ns_ * 1e3));
    return (hi >= 0 ? hi / period_ps_ : -((-hi + period_ps_ - 1) / period_ps_)) + 1;
}

void WaveformSynth::add(const Arrival& a, std::int64_t j0, std::span<double> out) const {
    const std::int64_t lo = std::max(first_sample(a.delay_ps), j0);
    const std::int64_t hi =
        std::min(end_sample(a.delay_ps), j0 + static_cast<std::int64_t>(out.size()));
    const double inv_step = 1.0 / step_ns_;
    const double last = static_cast<double>(table_.size() - 2);
    for (std::int64_t j = lo; j < hi; ++j) {
        // Position in the table of t_j − t_a, computed from integer ps so it is exact.
        const double u = 1e-3 * static_cast<double>(j * period_ps_ - a.delay_ps);
        const double v = (u - begin_ns_) * inv_step;
        if (!(v >= 0.0) || v > last) continue;
        const auto m = static_cast<std::size_t>(v);
        const double f = v - static_cast<double>(m);
        out[static_cast<std::size_t>(j - j0)] +=
            static_cast<double>(a.pe) * (table_[m] + f * (table_[m + 1] - table_[m]));
    }
}

}  // namespace mirage::physics
