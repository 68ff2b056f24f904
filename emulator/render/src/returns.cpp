// SPDX-License-Identifier: Apache-2.0
// Returns: a pulse's sub-ray hits merged into echoes (c·τ/2 apart), queued for shading.
#include <limits>

#include "shading.hpp"

namespace mirage::render {
namespace {

// Insertion sort by range (ties by sub-ray): a handful of sub-rays.
void sort_by_range(std::span<Contribution> contrib) {
    for (std::size_t a = 1; a < contrib.size(); ++a) {
        const Contribution c = contrib[a];
        std::size_t b = a;
        for (; b > 0 && (contrib[b - 1].range_m > c.range_m ||
                         (contrib[b - 1].range_m == c.range_m && contrib[b - 1].sub > c.sub));
             --b)
            contrib[b] = contrib[b - 1];
        contrib[b] = c;
    }
}

}  // namespace

// One sub-ray per pulse: its hit, if within the receiver's ranges, is the pulse's only return.
// Hits and misses alternate unpredictably, so this runs without branches: every pulse writes a
// candidate and only one with a return advances the count.
void PulseShader::single_returns(const RayBatch& g, const std::vector<Hit>& hits,
                                 const double* terms, double k, ShadeScratch& scratch,
                                 RenderStats& stats) const {
    const std::size_t n = g.specs.size();
    const double lo = sensor_.receiver.min_range_m, hi = sensor_.receiver.max_range_m;
    scratch.pending.resize(n);
    PendingReturn* out = scratch.pending.data();
    std::size_t np = 0;
    std::uint64_t close = 0, missed = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t r = g.first_ray[i];
        const double range = hits[r].t;  // +inf on a miss
        const bool near = range < lo;
        const bool in = !near & (range <= hi);
        out[np] = {range, k * terms[r], static_cast<std::uint32_t>(i), r, 0};
        np += in;
        close += near;
        missed += !near & !in;
    }
    scratch.pending.resize(np);
    for (PendingReturn& p : scratch.pending) {
        if (p.power_w < 0.0) {  // a specular lobe (see ray_terms): its BRDF per hit
            const Hit& h = hits[p.hit];
            const double t = -terms[p.hit] * physics::monostatic_brdf(scene_.materials[h.material],
                                                                      incidence(g.rays[p.hit], h));
            p.power_w = k * t;
        }
    }
    stats.pulses += n;
    stats.too_close += close;
    stats.misses += missed;
}

// Several sub-rays per pulse: their hits merge into returns (split_returns when they spread over
// more than c·τ/2).
void PulseShader::clustered_returns(const RayBatch& g, const std::vector<Hit>& hits,
                                    const RayView& rays, const double* terms,
                                    const std::vector<double>& weighted_k, ShadeScratch& scratch,
                                    RenderStats& stats) const {
    const std::size_t n = g.specs.size();
    const PathScratch* paths = scratch.paths ? &scratch.path : nullptr;
    scratch.contributions.resize(weighted_k.size() + (paths ? paths->most : 0));
    Contribution* buffer = scratch.contributions.data();  // a pulse's: buffer[0, count)
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t r = g.first_ray[i];
        if (g.planar(i)) {
            // One plane (adaptive_footprint.cpp): its closed form is the pulse's one return.
            const PlaneFootprint& f = g.plane[i];
            scratch.pending.push_back({f.range_m, power_k_ * terms[r] * f.power_factor,
                                       static_cast<std::uint32_t>(i), r, 0});
            stats.pulses++;
            continue;
        }
        const PulseHits ph = gather_hits(&hits[r], rays, terms + r, weighted_k, buffer, paths, r,
                                         static_cast<std::uint32_t>(i));
        stats.pulses++;
        if (ph.count == 0) {
            if (ph.any_close)
                stats.too_close++;
            else
                stats.misses++;
            continue;
        }
        // Usual case: every sub-ray hit lies within c·τ/2 of the others, so no gap can split
        // them and one return takes them all, without sorting.
        const Return one{ph.sum_p > 0 ? ph.sum_rp / ph.sum_p : buffer[0].range_m, ph.sum_p,
                         ph.best_sub};
        const auto ii = static_cast<std::uint32_t>(i);
        const std::span<Contribution> contrib(buffer, ph.count);
        if (ph.hi - ph.lo <= separation_m_) {
            add_returns(ii, r, std::span<const Return>(&one, 1), scratch);
            continue;
        }
        set_patch_depths(&hits[r], rays, r, contrib);
        split_returns(ii, r, contrib, scratch);
    }
}

// A pulse's sub-ray hits within the receiver's ranges into `buffer`, with the one-return
// aggregates accumulated on the way (in sub-ray order, as a split into several returns would sum
// them): range span, power-weighted range, power, and the strongest sub-ray (the first of equals).
PulseShader::PulseHits PulseShader::gather_hits(const Hit* h, const RayView& rays,
                                                const double* term,
                                                const std::vector<double>& weighted_k,
                                                Contribution* buffer, const PathScratch* paths,
                                                std::uint32_t r, std::uint32_t i) const {
    const auto& rx = sensor_.receiver;
    PulseHits out;
    out.lo = std::numeric_limits<double>::infinity();
    out.hi = -out.lo;
    double best_p = -1;
    // Entry q (relative to the pulse's first sub-ray) with its sub-ray's power factor k.
    const auto take = [&](std::uint32_t q, double k) {
        if (!h[q].hit()) return;
        const double range = h[q].t;
        if (range < rx.min_range_m) {
            out.any_close = true;
            return;
        }
        if (range > rx.max_range_m) return;
        double t = term[q];
        if (t < 0.0) {  // a specular lobe: the BRDF depends on incidence
            const double cos_inc = incidence(rays[r + q], h[q]);
            t = -t * physics::monostatic_brdf(scene_.materials[h[q].material], cos_inc);
        }
        const double p = k * t;
        // With continuations a surface that reflects nothing (clear glass, a pure mirror) must
        // not make a return of its own; without, the first-hit path keeps its behaviour.
        if (paths && !(p > 0.0)) return;
        buffer[out.count++] = {range, p, q, 0.0};
        out.lo = std::min(out.lo, range);
        out.hi = std::max(out.hi, range);
        out.sum_rp += range * p;
        out.sum_p += p;
        if (p > best_p) {
            best_p = p;
            out.best_sub = q;
        }
    };
    for (std::size_t s = 0; s < weighted_k.size(); ++s)
        take(static_cast<std::uint32_t>(s), weighted_k[s]);
    if (paths)
        for (const std::uint32_t e : paths->of_pulse(i))
            take(e - r, weighted_k[paths->sub[e - paths->own]]);
    return out;
}

// Each hit's patch depth, R·Δ·tan θ (cos θ floored at 0.01: at most 100·R·Δ).
void PulseShader::set_patch_depths(const Hit* h, const RayView& rays, std::uint32_t r,
                                   std::span<Contribution> contrib) const {
    for (Contribution& b : contrib) {
        const double cos_inc = std::max(0.01, incidence(rays[r + b.sub], h[b.sub]));
        const double tan_inc = std::sqrt(std::max(0.0, 1.0 - cos_inc * cos_inc)) / cos_inc;
        b.half_depth_m = 0.5 * b.range_m * cell_rad_ * tan_inc;
    }
}

// Sub-ray hits spread over more than c·τ/2: sorted by range and split where the gap exceeds it
// (two surfaces closer than that blend into one echo); then the reported ones are emitted. A
// sub-ray samples a patch of the footprint one sub-ray spacing Δ wide, which on a surface at
// incidence θ spans R·Δ·tan θ in range: the gap is measured between these patches, not their
// centres. Otherwise a continuous surface seen at grazing incidence (ground far ahead) falls
// apart into several returns wherever adjacent sub-rays are more than c·τ/2 apart in range; that
// depends on Δ, hence on the sub-ray count, and the strongest piece carried as little as 41 % of
// the pulse's power (19 sub-rays) where 37 kept one return.
void PulseShader::split_returns(std::uint32_t i, std::uint32_t first_hit,
                                std::span<Contribution> contrib, ShadeScratch& scratch) const {
    sort_by_range(contrib);
    ReturnSum sums[8];
    const int count = group_returns(contrib, sums);
    // Which returns are reported: the strongest when one is kept, else the nearest ones.
    auto to_return = [&](const ReturnSum& r) {
        return Return{r.p > 0 ? r.rp / r.p : contrib.front().range_m, r.p, r.best_sub};
    };
    Return chosen[8];
    std::size_t kept = 0;
    const int max_returns = std::clamp(sensor_.receiver.max_returns, 1, 8);
    if (max_returns == 1) {
        int best = 0;
        for (int k = 1; k < count; ++k)
            if (sums[k].p > sums[best].p) best = k;
        chosen[kept++] = to_return(sums[best]);
    } else {
        for (int k = 0; k < count && kept < std::size_t(max_returns); ++k)
            chosen[kept++] = to_return(sums[k]);
    }
    add_returns(i, first_hit, std::span<const Return>(chosen, kept), scratch);
}

// Hits sorted by range into returns (at most 8), a new one wherever the gap between patches
// exceeds c·τ/2. Returns how many.
int PulseShader::group_returns(std::span<const Contribution> contrib, ReturnSum (&sums)[8]) const {
    int count = 0;
    double last_end = -1e300;  // the far end of the current return's patches
    for (const Contribution& c : contrib) {
        if (count == 0 || c.range_m - c.half_depth_m - last_end > separation_m_) {
            if (count == 8) break;
            ++count;
        }
        ReturnSum& r = sums[count - 1];
        r.rp += c.range_m * c.power_w;
        r.p += c.power_w;
        if (c.power_w > r.best_p) {
            r.best_p = c.power_w;
            r.best_sub = c.sub;
        }
        last_end = std::max(last_end, c.range_m + c.half_depth_m);
    }
    return count;
}

// Queues a pulse's reported returns (nearest first) for drawing and emission.
void PulseShader::add_returns(std::uint32_t i, std::uint32_t first_hit,
                              std::span<const Return> returns, ShadeScratch& scratch) const {
    std::uint32_t k = 0;
    for (const Return& r : returns)
        scratch.pending.push_back({r.range_m, r.power_w, i, first_hit + r.best_sub, k++});
}

}  // namespace mirage::render
