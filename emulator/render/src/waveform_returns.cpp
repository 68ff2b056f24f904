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

// Arrivals (sorted) in clusters become two that keep their photo-electrons and their delays'
// mean, variance and skew (physics::merge_arrivals): the waveform then differs from theirs by
// the fourth moment's term, ∝ (cluster width)⁴ times the pulse's fourth derivative, and a
// footprint's sub-rays on one facet cost two syntheses instead of one per sub-ray. Clusters span
// up to σ_p/2 for a Gaussian pulse; a measured pulse may have corners, where that term is not
// small, and keeps Δt/32 (docs/time-resolved.md §12).
void PulseShader::merge_close_arrivals(std::vector<physics::Arrival>& arrivals) const {
    physics::merge_arrivals(arrivals, merge_window_ps_);
}

// The batch's waveforms in three passes: each pulse's arrivals and sample groups; every group's
// samples synthesised, noised and digitised together (a pulse has a few tens of samples, too few
// for the generator's and digitiser's loops to vectorise one pulse at a time); then each pulse's
// echoes.
void PulseShader::waveform_returns(const RayBatch& g, const std::vector<Hit>& hits,
                                   const double* terms, const std::vector<double>& weighted_k,
                                   ShadeScratch& scratch, ShadedPoints& out) const {
    scratch.echo_fields.clear();
    scratch.deviation_jobs.clear();
    scratch.pulse_waves.clear();
    scratch.wave_arrivals.clear();
    scratch.groups.clear();
    for (std::uint32_t i = 0; i < g.specs.size(); ++i) {
        out.stats.pulses++;
        const bool close = gather_pulse(g, hits, terms, weighted_k, i, scratch);
        if (scratch.pulse_waves.empty() || scratch.pulse_waves.back().i != i) {
            if (close)
                out.stats.too_close++;
            else
                out.stats.misses++;
        }
    }
    digitise_batch(g.first, scratch);
    for (const PulseWave& w : scratch.pulse_waves) detect_pulse(g.first, w, scratch, out);
    fit_deviations(scratch);
}

// Pulse i's arrivals (sorted, close ones merged, times its energy factor and each group's
// speckle) and sample groups appended to the batch's, unless nothing arrives; true if a hit
// was closer than the receiver's minimum range.
bool PulseShader::gather_pulse(const RayBatch& g, const std::vector<Hit>& hits, const double* terms,
                               const std::vector<double>& weighted_k, std::uint32_t i,
                               ShadeScratch& scratch) const {
    auto& arrivals = scratch.arrivals;
    const bool close = pulse_arrivals(g, hits, terms, weighted_k, i, arrivals,
                                      scratch.paths ? &scratch.path : nullptr);
    if (arrivals.empty() && volume_pe_.empty()) return close;
    physics::sort_by_delay(arrivals, scratch.sorted);
    merge_close_arrivals(arrivals);
    const std::uint64_t pulse = g.first + i;
    const double energy = energy_factor(pulse);
    if (energy != 1.0)
        for (auto& a : arrivals) a.pe = static_cast<float>(a.pe * energy);
    PulseWave w{i, scratch.wave_arrivals.size(),        0,     scratch.groups.size(),
                0, floor_pe_per_sample(hits, arrivals), energy};
    scratch.wave_arrivals.insert(scratch.wave_arrivals.end(), arrivals.begin(), arrivals.end());
    w.b = scratch.wave_arrivals.size();
    sample_groups(arrivals, w.a, scratch.groups);
    w.g1 = scratch.groups.size();
    std::optional<core::PulseRng> speckle;  // one factor per group: per surface, nearly
    if (speckle_on()) speckle.emplace(opt_.seed, pulse, kSpeckleStream);
    std::size_t at = w.g0 > 0 ? scratch.groups[w.g0 - 1].end() : 0;
    for (std::size_t k = w.g0; k < w.g1; ++k) {
        SampleGroup& grp = scratch.groups[k];
        if (speckle) {
            const double factor = physics::speckle_factor(*speckle, speckle_m_);
            for (std::size_t a = grp.a; a < grp.b; ++a)
                scratch.wave_arrivals[a].pe =
                    static_cast<float>(scratch.wave_arrivals[a].pe * factor);
        }
        grp.at = at;
        at = grp.end();
    }
    scratch.pulse_waves.push_back(w);
    return close;
}

// Every group's expected photo-electrons per sample (the floor, its arrivals, the atmosphere's
// backscatter), its noise and its digitised counts. Group k of a pulse draws Philox blocks of
// the pulse's stream 1 after those of its groups before it (block b's word m: sample 4b + m).
void PulseShader::digitise_batch(std::uint64_t first_pulse, ShadeScratch& scratch) const {
    const bool noisy = opt_.noise;
    const std::size_t n = scratch.groups.empty() ? 0 : scratch.groups.back().end();
    scratch.wave.assign(n, 0.0);
    scratch.pulse.clear();
    scratch.block.clear();
    for (const PulseWave& w : scratch.pulse_waves) {
        std::uint32_t block = 0;
        for (std::size_t k = w.g0; k < w.g1; ++k) {
            const SampleGroup& grp = scratch.groups[k];
            const std::span<double> wave(scratch.wave.data() + grp.at, grp.size());
            if (noisy) std::fill(wave.begin(), wave.end(), w.floor_pe);
            for (std::size_t a = grp.a; a < grp.b; ++a)
                synth_->add(scratch.wave_arrivals[a], grp.j0, wave);
            if (!volume_pe_.empty()) add_volume(grp.j0, wave, w.energy);
            if (!noisy) continue;
            for (std::size_t b = 0; b < grp.blocks(); ++b) {
                scratch.pulse.push_back(first_pulse + w.i);
                scratch.block.push_back(block++);
            }
        }
    }
    if (noisy) normals_of_blocks(scratch.block.size(), scratch.wave_z, scratch);
    scratch.counts.resize(n);
    linear_->digitise(scratch.wave.data(), noisy ? scratch.wave_z.data() : nullptr, n,
                      scratch.counts.data());
}

// Pulse w's echoes, group by group, as pending returns (and its recorded window).
void PulseShader::detect_pulse(std::uint64_t first_pulse, const PulseWave& w, ShadeScratch& scratch,
                               ShadedPoints& out) const {
    scratch.wave_first = scratch.groups[w.g0].j0;
    if (opt_.waveform_samples > 0) scratch.record.assign(opt_.waveform_samples, NAN);
    scratch.echoes.resize(kMaxEchoes);
    std::size_t found = 0;
    for (std::size_t k = w.g0; k < w.g1 && found < kMaxEchoes; ++k)
        detect_group(scratch.groups[k], w.floor_pe, found, scratch);
    scratch.echoes.resize(found);
    const std::span<const physics::Arrival> arrivals(scratch.wave_arrivals.data() + w.a, w.b - w.a);
    if (found == 0) {
        if (arrivals.empty())
            out.stats.misses++;  // only the atmosphere, below the threshold
        else
            out.stats.voids++;  // light arrived, nothing crossed the threshold
        return;
    }
    std::uint32_t wave = core::PointRecord::kNoWave;
    if (opt_.waveform_samples > 0) wave = record_pulse(first_pulse + w.i, w, scratch, out.samples);
    add_echoes(w.i, arrivals, wave, scratch);
}

// Background (sun on the strongest arrival's surface, path radiance) and dark photo-electrons
// expected in one sample.
double PulseShader::floor_pe_per_sample(const std::vector<Hit>& hits,
                                        std::span<const physics::Arrival> arrivals) const {
    return (linear_->dark_rate_per_ns() + background_per_ns(hits, arrivals)) * synth_->period_ns();
}

// Background photo-electrons per ns: the strongest arrival's surface under the sun and the path
// radiance, over the receiver's pixel (docs/physics.md eqs. 6–10 per unit time); 0 without light.
double PulseShader::background_per_ns(const std::vector<Hit>& hits,
                                      std::span<const physics::Arrival> arrivals) const {
    if (arrivals.empty() || !(sun_up_ || env_.path_radiance_w_m2_sr_um > 0.0)) return 0.0;
    const auto strongest = std::max_element(
        arrivals.begin(), arrivals.end(), [](const auto& a, const auto& b) { return a.pe < b.pe; });
    const Hit& h = hits[strongest->hit];
    const double cos_sun =
        sun_up_ ? h.nx * to_sun_.x() + h.ny * to_sun_.y() + h.nz * to_sun_.z() : 0.0;
    return radiometry_.background_electrons(h.t, diffuse_brdf_[h.material], cos_sun) /
           (radiometry_.integration_time_s() * 1e9);
}

// One group's digitised counts searched for echoes, appended from scratch.echoes[found].
void PulseShader::detect_group(const SampleGroup& g, double floor_pe, std::size_t& found,
                               ShadeScratch& scratch) const {
    const bool noisy = opt_.noise;
    const std::size_t n = g.size();
    const double* counts = scratch.counts.data() + g.at;
    if (opt_.waveform_samples > 0) record_group(g, scratch);
    const double floor = noisy ? floor_pe : 0.0;
    std::size_t got = linear_->find_echoes(counts, n, g.j0, floor, noisy,
                                           scratch.echoes.data() + found, kMaxEchoes - found);
    const auto& p = linear_->params();
    if (p.timing == sensor::EchoTiming::Decomposition)
        got = linear_->decompose(counts, n, g.j0, floor, noisy, sigma_p_ns_,
                                 scratch.echoes.data() + found, got, kMaxEchoes - found);
    time_echoes(g, p.offset_counts + p.gain_counts_per_pe * floor, found, found + got, scratch);
    found += got;
}

// The echoes [from, to) of group g timed as the detector's timing says (docs/time-resolved.md
// §12), each with a job for its deviation from the fit (the decomposition sets its own).
void PulseShader::time_echoes(const SampleGroup& g, double baseline, std::size_t from,
                              std::size_t to, ShadeScratch& scratch) const {
    const auto& p = linear_->params();
    if (p.timing == sensor::EchoTiming::Decomposition) return;
    const double* counts = scratch.counts.data() + g.at;
    for (std::size_t e = from; e < to; ++e) {
        physics::Echo& echo = scratch.echoes[e];
        const double* own = counts + (echo.first - g.j0);  // the echo's first sample
        echo.tag = static_cast<std::uint32_t>(scratch.deviation_jobs.size());
        scratch.deviation_jobs.push_back({g.at + std::size_t(echo.first - g.j0), echo.first,
                                          echo.end, echo.time_ns, echo.amplitude_counts,
                                          echo.sigma_ns, baseline});
        if (p.timing == sensor::EchoTiming::ConstantFraction) {
            const double edge =
                linear_->leading_edge_ns(counts, g.size(), g.j0, baseline, echo, p.cfd_fraction);
            if (!std::isnan(edge)) echo.time_ns = edge + cfd_offset_ns_;
        } else if (matched_) {
            echo.time_ns = matched_time_ns(echo, own, baseline, scratch);
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

// Each reported echo's RMS difference between its samples and its fitted Gaussian on the
// baseline (counts): near the digitiser's noise for a clean echo; larger where echoes overlap or
// the pulse is not Gaussian (a measured shape, a surface that skews it). The batch's at once: an
// echo has a few tens of samples, too few for its exponentials to fill a vector loop, so all the
// jobs' Gaussians are made in one loop (fit_gaussians), then each echo's squares are summed in
// four lanes, sample k in lane k mod 4 (the order of the loop per echo this replaced: the same
// sums).
void PulseShader::fit_deviations(ShadeScratch& scratch) const {
    fit_gaussians(scratch);
    const std::vector<double>& g = scratch.fit_x;
    std::size_t s = 0;
    for (const DeviationJob& j : scratch.deviation_jobs) {
        // (an echo without samples keeps the deviation 0 it was made with)
        if (j.field == DeviationJob::kNoField || j.end <= j.first) continue;
        const auto n = static_cast<std::size_t>(j.end - j.first);
        const double* y = scratch.counts.data() + j.at;
        double acc[4] = {0, 0, 0, 0};
        for (std::size_t k = 0; k < n; ++k) {
            const double d = y[k] - (j.baseline + j.amplitude * g[s + k]);
            acc[k % 4] += d * d;
        }
        s += n;
        scratch.echo_fields[j.field].deviation =
            static_cast<float>(std::sqrt(((acc[0] + acc[1]) + (acc[2] + acc[3])) / double(n)));
    }
}

// scratch.fit_x: the reported echoes' fitted Gaussians exp(−(t_k − t_fit)²/(2σ²)) at their
// samples, echo after echo.
void PulseShader::fit_gaussians(ShadeScratch& scratch) const {
    const double dt = synth_->period_ns();
    std::size_t total = 0;
    for (const DeviationJob& j : scratch.deviation_jobs)
        if (j.field != DeviationJob::kNoField && j.end > j.first)
            total += std::size_t(j.end - j.first);
    auto& x = scratch.fit_x;
    x.resize(total);
    std::size_t at = 0;
    for (const DeviationJob& j : scratch.deviation_jobs) {
        if (j.field == DeviationJob::kNoField || j.end <= j.first) continue;
        const double inv = j.sigma_ns > 0 ? 1.0 / (2.0 * j.sigma_ns * j.sigma_ns) : 0.0;
        // The sample's index as its 64-sample chunk's start plus a 32-bit offset: exact, and
        // AVX2 converts 32-bit integers in vectors (64-bit ones it does not).
        for (std::int64_t k0 = 0; k0 < j.end - j.first; k0 += 64) {
            const double start = double(j.first + k0);
            const auto m =
                static_cast<std::int32_t>(std::min<std::int64_t>(64, j.end - j.first - k0));
            double* out = x.data() + at;
            for (std::int32_t k = 0; k < m; ++k) {
                const double u = (start + double(k)) * dt - j.time_ns;
                out[k] = -u * u * inv;
            }
            at += std::size_t(m);
        }
    }
    for (double& v : x) v = core::exp_poly(v);
}

// n standard normals of the pulse's stream 1 into z, from Philox block `block` on (block b's
// word k is sample 4b + k).
void PulseShader::draw_normals(std::uint64_t pulse, std::size_t n, std::uint32_t block,
                               std::vector<double>& z, ShadeScratch& scratch) const {
    const std::size_t blocks = (n + 3) / 4;
    scratch.pulse.assign(blocks, pulse);
    scratch.block.resize(blocks);
    for (std::size_t b = 0; b < blocks; ++b)
        scratch.block[b] = block + static_cast<std::uint32_t>(b);
    normals_of_blocks(blocks, z, scratch);
}

// The normals of Philox blocks (scratch.pulse[b], scratch.block[b]) of stream 1 into z, four a
// block in order: the generator's loops run over all of them at once.
void PulseShader::normals_of_blocks(std::size_t blocks, std::vector<double>& z,
                                    ShadeScratch& scratch) const {
    for (auto& w : scratch.words) w.resize(blocks);
    core::philox_blocks(opt_.seed, kWaveformStream, scratch.pulse.data(), scratch.block.data(),
                        blocks,
                        {scratch.words[0].data(), scratch.words[1].data(), scratch.words[2].data(),
                         scratch.words[3].data()});
    scratch.sample_words.resize(4 * blocks);
    for (std::size_t b = 0; b < blocks; ++b)
        for (std::size_t k = 0; k < 4; ++k) scratch.sample_words[4 * b + k] = scratch.words[k][b];
    z.resize(4 * blocks);
    core::normals_of_words(scratch.sample_words.data(), 4 * blocks, z.data());
}

// A measured (skewed) pulse: the echo's time is where the emitted shape, slid over its samples,
// correlates best (normalised cross-correlation, the matched filter): exact for one echo at any
// phase of the clock, where a three-point fit of a Gaussian to a skewed pulse is biased by
// centimetres. Delays ±1.5 samples about the fit, in steps of Δt/32, then a parabola.
double PulseShader::matched_time_ns(const physics::Echo& e, const double* y, double baseline,
                                    ShadeScratch& scratch) const {
    const auto n = static_cast<std::size_t>(e.end - e.first);
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
void PulseShader::add_echoes(std::uint32_t i, std::span<const physics::Arrival> arrivals,
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
        if (linear_->params().timing != sensor::EchoTiming::Decomposition)
            scratch.deviation_jobs[e.tag].field = scratch.echo_fields.size() - 1;
    }
}

}  // namespace mirage::render
