// SPDX-License-Identifier: Apache-2.0
// The linear-mode detector in the pipeline (docs/time-resolved.md §2, §7): per pulse, the
// sub-ray hits become arrivals, the arrivals an expected waveform on the digitiser's clock, the
// waveform digitised counts (noise drawn from the pulse's stream 1) and the counts echoes.
#include <algorithm>
#include <cmath>
#include <optional>

#include "mirage/core/error.hpp"
#include "mirage/core/exp_poly.hpp"
#include "mirage/core/rng.hpp"
#include "mirage/physics/speckle.hpp"
#include "shading.hpp"

namespace mirage::render {
namespace {

constexpr double kPsPerMeterTwoWay = 2e12 / physics::kSpeedOfLightMPerS;
constexpr double kMetersPerNsOneWay = 0.5e-9 * physics::kSpeedOfLightMPerS;
constexpr std::uint32_t kWaveformStream = 1;  // stream 0: the discrete returns' draws

}  // namespace

bool PulseShader::pulse_arrivals(const RayBatch& g, const std::vector<Hit>& hits,
                                 const double* terms, const std::vector<double>& weighted_k,
                                 std::uint32_t i, std::vector<physics::Arrival>& out,
                                 const PathScratch* paths) const {
    const auto& rx = sensor_.receiver;
    const double e_per_w = radiometry_.laser_electrons(1.0);
    const RayView rays = rays_of(g, paths);
    bool close = false;
    out.clear();
    // Batch entry e with its sub-ray's power factor k.
    const auto take = [&](std::uint32_t e, double k) {
        const Hit& h = hits[e];
        if (!h.hit()) return;
        if (h.t < rx.min_range_m) {
            close = true;
            return;
        }
        if (h.t > rx.max_range_m) return;
        double t = terms[e];
        if (t < 0.0)  // a specular lobe: the BRDF depends on incidence
            t = -t * physics::monostatic_brdf(scene_.materials[h.material], incidence(rays[e], h));
        const double pe = k * t * e_per_w;
        if (!(pe > 0.0)) return;
        // h.t > 0: rounding by adding ½ (llround was a library call per sub-ray).
        const auto delay = static_cast<std::int64_t>(h.t * kPsPerMeterTwoWay + 0.5);
        out.push_back({delay, static_cast<float>(pe), e});
    };
    const std::uint32_t r = g.first_ray[i];
    if (g.planar(i)) {
        plane_arrivals(g.plane[i], terms[r] * power_k_ * e_per_w, r, out);
        return false;
    }
    for (std::uint32_t s = 0; s < weighted_k.size(); ++s) take(r + s, weighted_k[s]);
    if (paths)
        for (const std::uint32_t e : paths->of_pulse(i))
            take(e, weighted_k[paths->sub[e - paths->own]]);
    return close;
}

// A plane's footprint (adaptive_footprint.cpp) as three arrivals at R̄ and R̄ ± √3·σ_R with 1/6,
// 2/3, 1/6 of the photo-electrons (Gauss–Hermite): the delays' mean and variance, and a Gaussian
// spread's fourth moment, as the footprint's sub-rays would give them.
void PulseShader::plane_arrivals(const PlaneFootprint& f, double central_pe, std::uint32_t hit,
                                 std::vector<physics::Arrival>& out) const {
    const double pe = central_pe * f.power_factor;
    if (!(pe > 0.0)) return;
    const double spread = std::sqrt(3.0) * f.sigma_m;
    const double ranges[3] = {f.range_m - spread, f.range_m, f.range_m + spread};
    const double share[3] = {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0};
    for (int k = 0; k < 3; ++k)
        out.push_back({static_cast<std::int64_t>(ranges[k] * kPsPerMeterTwoWay + 0.5),
                       static_cast<float>(pe * share[k]), hit});
}

// Arrivals (sorted) less than Δt/32 apart merge into one at their photo-electron-weighted mean
// delay, with the strongest one's hit: the waveform keeps its energy and centroid, and its
// variance changes by less than (Δt/64)² (0.015 % of a 4 ns pulse's at 1 GS/s), while a footprint
// on one facet square to the beam costs one synthesis instead of one per sub-ray.
void PulseShader::merge_close_arrivals(std::vector<physics::Arrival>& arrivals) const {
    const double window_ps = 1e3 * synth_->period_ns() / physics::WaveformSynth::kSubSteps;
    std::size_t out = 0;
    for (std::size_t a = 0; a < arrivals.size();) {
        const std::int64_t start = arrivals[a].delay_ps;
        double pe = 0, pe_delay = 0, best = -1;
        std::uint32_t hit = arrivals[a].hit;
        std::size_t b = a;
        for (; b < arrivals.size() && double(arrivals[b].delay_ps - start) < window_ps; ++b) {
            pe += arrivals[b].pe;
            pe_delay += double(arrivals[b].pe) * double(arrivals[b].delay_ps - start);
            if (arrivals[b].pe > best) {
                best = arrivals[b].pe;
                hit = arrivals[b].hit;
            }
        }
        arrivals[out++] = {start + std::llround(pe_delay / pe), static_cast<float>(pe), hit};
        a = b;
    }
    arrivals.resize(out);
}

void PulseShader::waveform_returns(const RayBatch& g, const std::vector<Hit>& hits,
                                   const double* terms, const std::vector<double>& weighted_k,
                                   ShadeScratch& scratch, ShadedPoints& out) const {
    auto& arrivals = scratch.arrivals;
    scratch.echo_fields.clear();
    for (std::uint32_t i = 0; i < g.specs.size(); ++i) {
        const bool close = pulse_arrivals(g, hits, terms, weighted_k, i, arrivals,
                                          scratch.paths ? &scratch.path : nullptr);
        out.stats.pulses++;
        const auto missed = [&] {
            if (close)
                out.stats.too_close++;
            else
                out.stats.misses++;
        };
        if (arrivals.empty() && volume_pe_.empty()) {
            missed();
            continue;
        }
        std::sort(arrivals.begin(), arrivals.end(),
                  [](const auto& a, const auto& b) { return a.delay_ps < b.delay_ps; });
        merge_close_arrivals(arrivals);
        scratch.energy = energy_factor(g.first + i);
        if (scratch.energy != 1.0)
            for (auto& a : arrivals) a.pe = static_cast<float>(a.pe * scratch.energy);
        const double floor_pe = floor_pe_per_sample(hits, scratch);
        detect_waveform(g.first + i, floor_pe, scratch);
        if (scratch.echoes.empty()) {
            if (arrivals.empty())
                missed();  // only the atmosphere, below the threshold
            else
                out.stats.voids++;  // light arrived, nothing crossed the threshold
            continue;
        }
        std::uint32_t wave = core::PointRecord::kNoWave;
        if (opt_.waveform_samples > 0)
            wave = record_pulse(g.first + i, floor_pe, scratch, out.samples);
        add_echoes(i, arrivals, wave, scratch);
    }
}

// Background (sun on the strongest arrival's surface, path radiance) and dark photo-electrons
// expected in one sample.
double PulseShader::floor_pe_per_sample(const std::vector<Hit>& hits, ShadeScratch& scratch) const {
    double rate_per_ns = linear_->dark_rate_per_ns();
    if (!scratch.arrivals.empty() && (sun_up_ || env_.path_radiance_w_m2_sr_um > 0.0)) {
        const auto strongest =
            std::max_element(scratch.arrivals.begin(), scratch.arrivals.end(),
                             [](const auto& a, const auto& b) { return a.pe < b.pe; });
        const Hit& h = hits[strongest->hit];
        const double cos_sun =
            sun_up_ ? h.nx * to_sun_.x() + h.ny * to_sun_.y() + h.nz * to_sun_.z() : 0.0;
        rate_per_ns += radiometry_.background_electrons(h.t, diffuse_brdf_[h.material], cos_sun) /
                       (radiometry_.integration_time_s() * 1e9);
    }
    return rate_per_ns * synth_->period_ns();
}

// The pulse's echoes into scratch.echoes, in time order: one waveform per group of arrivals
// whose pulses overlap (a footprint on two objects far apart costs two short waveforms, not
// the samples between them), the atmosphere's backscatter in the group it overlaps.
void PulseShader::detect_waveform(std::uint64_t pulse, double floor_pe,
                                  ShadeScratch& scratch) const {
    sample_groups(scratch);
    std::uint32_t block = 0;  // the pulse's next Philox block of stream 1
    scratch.wave_first = scratch.groups.front().j0;
    if (opt_.waveform_samples > 0) scratch.record.assign(opt_.waveform_samples, NAN);
    scratch.echoes.resize(kMaxEchoes);
    std::size_t found = 0;
    std::optional<core::PulseRng> speckle;  // one factor per group: per surface, nearly
    if (speckle_on()) speckle.emplace(opt_.seed, pulse, kSpeckleStream);
    for (const SampleGroup& g : scratch.groups) {
        if (found >= kMaxEchoes) break;
        if (speckle) scale_group(g, physics::speckle_factor(*speckle, speckle_m_), scratch);
        detect_group(pulse, g, floor_pe, block, found, scratch);
    }
    scratch.echoes.resize(found);
    scratch.next_block = block;
}

// The arrivals of group g times `factor` (its speckle).
void PulseShader::scale_group(const SampleGroup& g, double factor, ShadeScratch& scratch) const {
    for (std::size_t k = g.a; k < g.b; ++k)
        scratch.arrivals[k].pe = static_cast<float>(scratch.arrivals[k].pe * factor);
}

// One group's expected waveform, digitised (noise from Philox block `block` on) and searched for
// echoes, appended from scratch.echoes[found].
void PulseShader::detect_group(std::uint64_t pulse, const SampleGroup& g, double floor_pe,
                               std::uint32_t& block, std::size_t& found,
                               ShadeScratch& scratch) const {
    const bool noisy = opt_.noise;
    const auto n = static_cast<std::size_t>(g.j1 - g.j0);
    scratch.wave.assign(n, noisy ? floor_pe : 0.0);
    for (std::size_t k = g.a; k < g.b; ++k) synth_->add(scratch.arrivals[k], g.j0, scratch.wave);
    if (!volume_pe_.empty()) add_volume(g.j0, scratch.wave, scratch.energy);
    scratch.counts.resize(n);
    if (noisy) draw_normals(pulse, n, block, scratch);
    linear_->digitise(scratch.wave.data(), noisy ? scratch.wave_z.data() : nullptr, n,
                      scratch.counts.data());
    if (opt_.waveform_samples > 0) record_group(g.j0, scratch);
    const double floor = noisy ? floor_pe : 0.0;
    std::size_t got = linear_->find_echoes(scratch.counts.data(), n, g.j0, floor, noisy,
                                           scratch.echoes.data() + found, kMaxEchoes - found);
    const auto& p = linear_->params();
    if (p.timing == sensor::EchoTiming::Decomposition)
        got = linear_->decompose(scratch.counts.data(), n, g.j0, floor, noisy, sigma_p_ns_,
                                 scratch.echoes.data() + found, got, kMaxEchoes - found);
    time_echoes(g, p.offset_counts + p.gain_counts_per_pe * floor, found, found + got, scratch);
    found += got;
}

// The echoes [from, to) of group g timed as the detector's timing says (docs/time-resolved.md
// §12), with their deviation from the fit (the decomposition sets its own).
void PulseShader::time_echoes(const SampleGroup& g, double baseline, std::size_t from,
                              std::size_t to, ShadeScratch& scratch) const {
    const auto& p = linear_->params();
    if (p.timing == sensor::EchoTiming::Decomposition) return;
    const auto n = static_cast<std::size_t>(g.j1 - g.j0);
    for (std::size_t e = from; e < to; ++e) {
        physics::Echo& echo = scratch.echoes[e];
        echo.deviation = fit_deviation(echo, g.j0, baseline, scratch);
        if (p.timing == sensor::EchoTiming::ConstantFraction) {
            const double edge = linear_->leading_edge_ns(scratch.counts.data(), n, g.j0, baseline,
                                                         echo, p.cfd_fraction);
            if (!std::isnan(edge)) echo.time_ns = edge + cfd_offset_ns_;
        } else if (matched_) {
            echo.time_ns = matched_time_ns(echo, g.j0, baseline, scratch);
        }
    }
}

// The constant-fraction offset, measured as a receiver is calibrated: the detector's own edge
// on noise-free echoes of the emitted pulse at 32 phases of the clock, against their centroid.
double PulseShader::calibrate_cfd() const {
    const double period_ps = 1e3 * synth_->period_ns();
    const double fraction = linear_->params().cfd_fraction;
    double sum = 0;
    int counted = 0;
    std::vector<double> wave, counts;
    for (int k = 0; k < 32; ++k) {
        const auto delay = static_cast<std::int64_t>(std::llround(period_ps * (1000 + k / 32.0)));
        const std::int64_t j0 = synth_->first_sample(delay) - 1;
        wave.assign(static_cast<std::size_t>(synth_->end_sample(delay) + 1 - j0), 0.0);
        synth_->add({delay, 1000.0f, 0}, j0, wave);
        counts.resize(wave.size());
        linear_->digitise(wave.data(), nullptr, wave.size(), counts.data());
        physics::Echo e;
        if (linear_->find_echoes(counts.data(), counts.size(), j0, 0.0, false, &e, 1) != 1)
            continue;
        const double edge = linear_->leading_edge_ns(counts.data(), counts.size(), j0,
                                                     linear_->params().offset_counts, e, fraction);
        if (std::isnan(edge)) continue;
        sum += 1e-3 * double(delay) - edge;
        ++counted;
    }
    if (counted == 0)
        throw mirage::ConfigError("sensor '" + sensor_.name +
                                  "': detector.cfd_fraction: the pulse has no leading edge at " +
                                  std::to_string(fraction) + " of its peak on this clock");
    return sum / counted;
}

// The RMS difference between an echo's samples and its fitted Gaussian on the baseline (counts):
// near the digitiser's noise for a clean echo; larger where echoes overlap or the pulse is not
// Gaussian (a measured shape, a surface that skews it).
double PulseShader::fit_deviation(const physics::Echo& e, std::int64_t j0, double baseline,
                                  const ShadeScratch& scratch) const {
    const double dt = synth_->period_ns();
    const double inv = e.sigma_ns > 0 ? 1.0 / (2.0 * e.sigma_ns * e.sigma_ns) : 0.0;
    double sum = 0;
    for (std::int64_t j = e.first; j < e.end; ++j) {
        const double u = double(j) * dt - e.time_ns;
        const double model = baseline + e.amplitude_counts * core::exp_poly(-u * u * inv);
        const double r = scratch.counts[static_cast<std::size_t>(j - j0)] - model;
        sum += r * r;
    }
    return e.end > e.first ? std::sqrt(sum / double(e.end - e.first)) : 0.0;
}

// n standard normals of the pulse's stream 1 into scratch.wave_z, from Philox block `block` on
// (advanced past them): block b's word k is sample 4b + k. Batched, so the generator vectorises.
void PulseShader::draw_normals(std::uint64_t pulse, std::size_t n, std::uint32_t& block,
                               ShadeScratch& scratch) const {
    const std::size_t blocks = (n + 3) / 4;
    scratch.pulse.assign(blocks, pulse);
    scratch.block.resize(blocks);
    for (std::size_t b = 0; b < blocks; ++b)
        scratch.block[b] = block + static_cast<std::uint32_t>(b);
    block += static_cast<std::uint32_t>(blocks);
    for (auto& w : scratch.words) w.resize(blocks);
    core::philox_blocks(opt_.seed, kWaveformStream, scratch.pulse.data(), scratch.block.data(),
                        blocks,
                        {scratch.words[0].data(), scratch.words[1].data(), scratch.words[2].data(),
                         scratch.words[3].data()});
    scratch.wave_z.resize(4 * blocks);
    for (std::size_t k = 0; k < 4; ++k) {
        scratch.normals[k].resize(blocks);
        core::normals_of_words(scratch.words[k].data(), blocks, scratch.normals[k].data());
        for (std::size_t b = 0; b < blocks; ++b) scratch.wave_z[4 * b + k] = scratch.normals[k][b];
    }
}

// A measured (skewed) pulse: the echo's time is where the emitted shape, slid over its samples,
// correlates best (normalised cross-correlation, the matched filter): exact for one echo at any
// phase of the clock, where a three-point fit of a Gaussian to a skewed pulse is biased by
// centimetres. Delays ±1.5 samples about the fit, in steps of Δt/32, then a parabola.
double PulseShader::matched_time_ns(const physics::Echo& e, std::int64_t j0, double baseline,
                                    ShadeScratch& scratch) const {
    const auto n = static_cast<std::size_t>(e.end - e.first);
    const double* y = scratch.counts.data() + (e.first - j0);
    const double step_ps = 1e3 * synth_->period_ns() / physics::WaveformSynth::kSubSteps;
    constexpr int kHalf = 48;
    double score[2 * kHalf + 1];
    for (int k = -kHalf; k <= kHalf; ++k) {
        const auto d = static_cast<std::int64_t>(std::llround(e.time_ns * 1e3 + k * step_ps));
        scratch.pulse_template.assign(n, 0.0);
        synth_->add({d, 1.0f, 0}, e.first, scratch.pulse_template);
        double dot = 0, norm = 0;
        for (std::size_t j = 0; j < n; ++j) {
            dot += (y[j] - baseline) * scratch.pulse_template[j];
            norm += scratch.pulse_template[j] * scratch.pulse_template[j];
        }
        score[k + kHalf] = norm > 0 ? dot / std::sqrt(norm) : -INFINITY;
    }
    const int best = static_cast<int>(std::max_element(score, score + 2 * kHalf + 1) - score);
    double shift = best - kHalf;
    if (best > 0 && best < 2 * kHalf) {
        const double a = score[best - 1], b = score[best], c = score[best + 1];
        const double den = a - 2 * b + c;
        if (den < 0) shift += 0.5 * (a - c) / den;
    }
    return e.time_ns + 1e-3 * shift * step_ps;
}

// An echo's point fields; its place in the pulse's recorded window, if it lies inside it.
EchoFields PulseShader::echo_fields(const physics::Echo& e, std::uint32_t wave,
                                    std::int64_t wave_first) const {
    EchoFields f{static_cast<float>(e.amplitude_counts), static_cast<float>(e.sigma_ns),
                 static_cast<float>(e.deviation), 0.0f, core::PointRecord::kNoWave};
    if (wave == core::PointRecord::kNoWave) return f;
    const double period_ps = 1e3 * synth_->period_ns();
    const double at_ps = 1e3 * e.time_ns - double(wave_first) * period_ps;
    if (at_ps >= 0.0 && at_ps <= double(opt_.waveform_samples - 1) * period_ps) {
        f.wave = wave;
        f.wave_location_ps = static_cast<float>(at_ps);
    }
    return f;
}

// The reported echoes as pending returns: the strongest when one is kept, else the nearest
// ones (as the discrete detector chooses). Each takes material and normal from the strongest
// arrival within 2σ_p of it (else the nearest arrival).
void PulseShader::add_echoes(std::uint32_t i, const std::vector<physics::Arrival>& arrivals,
                             std::uint32_t wave, ShadeScratch& scratch) const {
    auto& echoes = scratch.echoes;
    const int max_returns = std::clamp(sensor_.receiver.max_returns, 1, 8);
    if (max_returns == 1) {
        const auto best = std::max_element(
            echoes.begin(), echoes.end(), [](const auto& a, const auto& b) { return a.pe < b.pe; });
        std::rotate(echoes.begin(), best, best + 1);
        echoes.resize(1);
    } else if (echoes.size() > std::size_t(max_returns)) {
        echoes.resize(static_cast<std::size_t>(max_returns));
    }
    const double e_per_w = radiometry_.laser_electrons(1.0);
    std::uint32_t k = 0;
    for (const physics::Echo& e : echoes) {
        const double t_ns = e.time_ns;
        const double t_ps = t_ns * 1e3, window = 2e3 * sigma_p_ns_;
        std::uint32_t strong = 0, near = 0;
        double best = -1, nearest = INFINITY;
        for (const physics::Arrival& a : arrivals) {
            const double d = std::abs(static_cast<double>(a.delay_ps) - t_ps);
            if (d <= window && a.pe > best) {
                best = a.pe;
                strong = a.hit;
            }
            if (d < nearest) {
                nearest = d;
                near = a.hit;
            }
        }
        // An echo with no surface within 2σ_p in the atmosphere's backscatter (or with no
        // surface at all) is the atmosphere's own.
        const bool volume = best < 0 && (arrivals.empty() || in_volume(t_ns));
        const std::uint32_t hit = volume ? kVolumeHit : best >= 0 ? strong : near;
        scratch.pending.push_back({t_ns * kMetersPerNsOneWay, e.pe / e_per_w, i, hit, k++});
        scratch.echo_fields.push_back(echo_fields(e, wave, scratch.wave_first));
    }
}

}  // namespace mirage::render
