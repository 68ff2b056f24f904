// SPDX-License-Identifier: Apache-2.0
// The atmosphere's volume backscatter in the waveform (docs/time-resolved.md §6): by the elastic
// lidar equation a slice dR at range R returns as a surface of BRDF·cos θ = β·dR would, so one
// sample (dR = c·Δt/2) expects k·β·dR·O(R)·exp(−2αR)/R² photo-electrons, with k the pulse's
// photo-electrons per unit of BRDF·cos θ·τ²/R², β = α/S and O the transmitter–receiver overlap.
// The atmosphere is homogeneous, so the samples are the same for every pulse: tabulated once.
#include <cmath>

#include "mirage/core/error.hpp"
#include "shading.hpp"

namespace mirage::render {
namespace {

constexpr double kMetersPerNsOneWay = 0.5e-9 * physics::kSpeedOfLightMPerS;
// Samples expecting less than this are left out: far below any digitiser's noise.
constexpr double kVolumeCutPe = 1e-4;
constexpr std::size_t kMaxVolumeSamples = 1 << 20;

}  // namespace

void PulseShader::init_volume() {
    const double s = env_.lidar_ratio_sr;
    const double alpha = env_.atmosphere.extinction_per_m;
    if (!(s > 0.0)) return;
    if (env_.atmosphere.scale_height_m > 0.0)
        throw mirage::ConfigError("sensor '" + sensor_.name +
                                  "': the volume backscatter (a lidar ratio) is modelled for "
                                  "homogeneous air, not an extinction profile (scale height)");
    if (!linear_)
        throw mirage::ConfigError("sensor '" + sensor_.name +
                                  "': the atmosphere's volume backscatter (a lidar ratio) needs "
                                  "a waveform digitiser (detector.type: linear)");
    const auto& rx = sensor_.receiver;
    const double dt = synth_->period_ns();
    const double k =
        power_k_ * radiometry_.laser_electrons(1.0) * (alpha / s) * kMetersPerNsOneWay * dt;
    const double r_o = rx.overlap_range_m;
    volume_first_ = static_cast<std::int64_t>(std::ceil(rx.min_range_m / kMetersPerNsOneWay / dt));
    for (std::int64_t j = std::max<std::int64_t>(volume_first_, 1);; ++j) {
        const double r = kMetersPerNsOneWay * dt * double(j);
        if (r > rx.max_range_m || volume_pe_.size() >= kMaxVolumeSamples) break;
        const double overlap = r_o > 0.0 ? 1.0 - std::exp(-(r / r_o) * (r / r_o)) : 1.0;
        const double pe = k * overlap * std::exp(-2.0 * alpha * r) / (r * r);
        if (pe < kVolumeCutPe && r > 3.0 * r_o) break;  // past the overlap, only decaying
        volume_pe_.push_back(pe);
    }
    if (volume_first_ == 0 && !volume_pe_.empty()) volume_first_ = 1;
    bool any = false;
    for (const double v : volume_pe_) any |= v >= kVolumeCutPe;
    if (!any) {
        volume_pe_.clear();  // clear air: nothing a detector could see
        return;
    }
    convolve_volume();
}

// The backscatter as received: each sample's slice spread by the emitted pulse's shape, as a
// hard target's arrival is (WaveformSynth), so a near-range rise is as wide as the pulse.
void PulseShader::convolve_volume() {
    const double dt_ps = 1e3 * synth_->period_ns();
    const auto delay = [&](std::int64_t j) { return std::llround(double(j) * dt_ps); };
    const std::int64_t last = volume_first_ + std::int64_t(volume_pe_.size()) - 1;
    const std::int64_t j0 = synth_->first_sample(delay(volume_first_));
    const std::int64_t j1 = synth_->end_sample(delay(last));
    std::vector<double> conv(static_cast<std::size_t>(j1 - j0), 0.0);
    for (std::size_t i = 0; i < volume_pe_.size(); ++i) {
        const std::int64_t j = volume_first_ + std::int64_t(i);
        synth_->add({delay(j), static_cast<float>(volume_pe_[i]), 0}, j0, conv);
    }
    volume_first_ = std::max<std::int64_t>(j0, 0);
    conv.erase(conv.begin(), conv.begin() + (volume_first_ - j0));
    volume_pe_ = std::move(conv);
}

// The pulse's sample groups in time order, appended to `groups` with its arrivals numbered from
// `base`: each arrival group, and the volume samples merged into the groups they overlap (or a
// group of their own).
void PulseShader::sample_groups(std::span<const physics::Arrival> arr, std::size_t base,
                                std::vector<SampleGroup>& groups) const {
    const std::int64_t v0 = volume_first_, v1 = v0 + std::int64_t(volume_pe_.size());
    bool volume = !volume_pe_.empty();
    for (std::size_t a = 0; a < arr.size();) {
        std::int64_t j0 = synth_->first_sample(arr[a].delay_ps);
        std::int64_t j1 = synth_->end_sample(arr[a].delay_ps);
        if (volume && v1 < j0) {
            groups.push_back({v0, v1, base + a, base + a});
            volume = false;
        } else if (volume && v0 <= j1) {
            j0 = std::min(j0, v0);
            j1 = std::max(j1, v1);
            volume = false;
        }
        std::size_t b = a + 1;
        for (; b < arr.size() && synth_->first_sample(arr[b].delay_ps) <= j1; ++b)
            j1 = std::max(j1, synth_->end_sample(arr[b].delay_ps));
        groups.push_back({j0, j1, base + a, base + b});
        a = b;
    }
    if (volume) groups.push_back({v0, v1, base + arr.size(), base + arr.size()});
}

// wave[j − j0] += the volume's photo-electrons in sample j (times the pulse's energy factor),
// where the two overlap.
void PulseShader::add_volume(std::int64_t j0, std::span<double> wave, double scale) const {
    const std::int64_t v0 = volume_first_, v1 = v0 + std::int64_t(volume_pe_.size());
    const std::int64_t lo = std::max(j0, v0), hi = std::min(j0 + std::int64_t(wave.size()), v1);
    for (std::int64_t j = lo; j < hi; ++j)
        wave[static_cast<std::size_t>(j - j0)] +=
            scale * volume_pe_[static_cast<std::size_t>(j - v0)];
}

bool PulseShader::in_volume(double time_ns) const {
    const double j = time_ns / synth_->period_ns();
    return !volume_pe_.empty() && j >= double(volume_first_) &&
           j < double(volume_first_) + double(volume_pe_.size());
}

}  // namespace mirage::render
