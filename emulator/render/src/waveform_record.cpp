// SPDX-License-Identifier: Apache-2.0
// The waveforms a render records (docs/time-resolved.md §13): per pulse with returns, a window of
// RenderOptions::waveform_samples digitised samples from the first sample its first arrival
// reaches, as a full-waveform digitiser stores them behind its trigger.
#include <algorithm>
#include <cmath>

#include "shading.hpp"

namespace mirage::render {

// One arrival group's digitised counts into the pulse's window.
void PulseShader::record_group(const SampleGroup& g, ShadeScratch& scratch) const {
    const auto window = static_cast<std::int64_t>(scratch.record.size());
    const double* counts = scratch.counts.data() + g.at;
    for (std::size_t k = 0; k < g.size(); ++k) {
        const std::int64_t at = g.j0 + static_cast<std::int64_t>(k) - scratch.wave_first;
        if (at >= window) break;
        scratch.record[static_cast<std::size_t>(at)] = counts[k];
    }
}

// Completes the window: samples between and after the arrival groups hold the floor (background
// and dark photo-electrons, noise drawn from the pulse's stream 1 after its groups' blocks). The
// window is appended to `samples`; returns the index of its first sample.
std::uint32_t PulseShader::record_pulse(std::uint64_t pulse, const PulseWave& w,
                                        ShadeScratch& scratch,
                                        std::vector<std::uint32_t>& samples) const {
    const bool noisy = opt_.noise;
    std::size_t gaps = 0;
    for (const double v : scratch.record) gaps += std::isnan(v);
    if (gaps > 0) {
        scratch.gap_wave.assign(gaps, noisy ? w.floor_pe : 0.0);
        scratch.gap_counts.resize(gaps);
        std::size_t used = 0;  // the Philox blocks of the pulse's groups
        for (std::size_t k = w.g0; k < w.g1; ++k) used += scratch.groups[k].blocks();
        if (noisy)
            draw_normals(pulse, gaps, static_cast<std::uint32_t>(used), scratch.gap_z, scratch);
        linear_->digitise(scratch.gap_wave.data(), noisy ? scratch.gap_z.data() : nullptr, gaps,
                          scratch.gap_counts.data());
        std::size_t g = 0;
        for (double& v : scratch.record)
            if (std::isnan(v)) v = scratch.gap_counts[g++];
    }
    const auto first = static_cast<std::uint32_t>(samples.size());
    // Counts are whole numbers but for a noise-free render, whose expected counts are kept.
    for (const double v : scratch.record)
        samples.push_back(static_cast<std::uint32_t>(std::nearbyint(std::max(0.0, v))));
    return first;
}

}  // namespace mirage::render
