// SPDX-License-Identifier: Apache-2.0
// Paths beyond the first hit (docs/time-resolved.md §5): a hit on a surface that transmits or
// mirrors continues the path in rounds, each round traced as one batch, until the receiver's
// max_path_depth. Transmission goes on along the same ray; a mirror sends it along the reflected
// direction from the hit. The return trip passes the same surfaces, so each multiplies the
// path's weight by its fraction squared. Below path_energy_threshold a path goes on by Russian
// roulette with its weight raised to the threshold (unbiased).
#include <algorithm>

#include "mirage/core/rng.hpp"
#include "shading.hpp"

namespace mirage::render {
namespace {

constexpr std::uint32_t kRouletteStream = 2;  // 0: discrete returns, 1: waveform noise
constexpr float kStep_m = 1e-3f;              // past the surface just left

}  // namespace

bool PulseShader::any_continuing(const std::vector<Hit>& hits) const {
    if (!continues_any_ || sensor_.receiver.max_path_depth < 2) return false;
    const auto last = static_cast<std::uint32_t>(continues_.size() - 1);
    bool any = false;
    for (const Hit& h : hits) any |= h.hit() & (continues_[std::min(h.material, last)] != 0);
    return any;
}

// The batch's own rays and hits as the paths' first round.
void PulseShader::start_paths(const RayBatch& g, const std::vector<Hit>& hits,
                              PathScratch& p) const {
    const std::size_t n = hits.size();
    p.rays = g.rays;
    p.hits = hits;
    p.weight.assign(n, 1.0);
    p.base.assign(n, 0.0);
    p.sub.resize(n);
    p.code.resize(n);
    p.pulse.resize(n);
    const auto subs = static_cast<std::uint32_t>(n / std::max<std::size_t>(1, g.specs.size()));
    for (std::uint32_t i = 0; i < g.specs.size(); ++i)
        for (std::uint32_t s = 0; s < subs; ++s) {
            const std::uint32_t r = g.first_ray[i] + s;
            p.sub[r] = p.code[r] = s;
            p.pulse[r] = i;
        }
}

bool PulseShader::trace_paths(const RayBatch& g, const std::vector<Hit>& hits, ShadeScratch& s,
                              RenderStats& stats) const {
    if (!any_continuing(hits)) return false;
    PathScratch& p = s.path;
    start_paths(g, hits, p);
    std::size_t from = 0, to = hits.size();
    for (int depth = 2; from < to; ++depth) {
        const bool last = depth > sensor_.receiver.max_path_depth;
        p.round_rays.clear();
        const std::size_t parent0 = to;
        for (std::size_t e = from; e < to; ++e) {
            const Hit& h = p.hits[e];
            if (!h.hit() || h.t > sensor_.receiver.max_range_m || !continues_[h.material]) continue;
            if (last) {
                stats.paths_cut++;
                continue;
            }
            spawn(g.first, e, p, stats);
        }
        if (p.round_rays.empty()) break;
        p.round_hits.assign(p.round_rays.size(), Hit{});
        renderer_.intersect(p.round_rays, p.round_hits);
        stats.path_segments += p.round_rays.size();
        for (std::size_t k = 0; k < p.round_rays.size(); ++k) {
            Hit h = p.round_hits[k];
            if (h.hit()) h.t = static_cast<float>(p.base[parent0 + k] + h.t);
            p.rays.push_back(p.round_rays[k]);
            p.hits.push_back(h);
        }
        from = to;
        to = p.hits.size();
    }
    index_by_pulse(g.specs.size(), hits.size(), p);
    return true;
}

// Entry e's continuations into the round: transmitted (same ray, beyond the surface) and
// mirrored (from the hit, reflected), each with its weight, base and code appended to `p`.
void PulseShader::spawn(std::uint64_t first_pulse, std::size_t e, PathScratch& p,
                        RenderStats& stats) const {
    const Hit h = p.hits[e];
    const Ray ray = p.rays[e];
    const scene::Material& m = scene_.materials[h.material];
    const double seg = h.t - p.base[e];  // along this entry's own ray
    const double weight = p.weight[e];
    const std::uint32_t sub = p.sub[e], pulse = p.pulse[e], parent_code = p.code[e];
    const auto add = [&](const Ray& r, double fraction, double base, std::uint32_t kind) {
        double w = weight * fraction * fraction;
        const std::uint32_t code = parent_code * 3u + kind;
        const double threshold = sensor_.receiver.path_energy_threshold;
        if (w < threshold) {
            core::PulseRng rng(opt_.seed ^ code, first_pulse + pulse, kRouletteStream);
            if (rng.uniform() * threshold >= w) {
                stats.paths_cut++;
                return;
            }
            w = threshold;
        }
        p.round_rays.push_back(r);
        p.weight.push_back(w);
        p.base.push_back(base);
        p.sub.push_back(sub);
        p.code.push_back(code);
        p.pulse.push_back(pulse);
    };
    if (m.transmission > 0.0) {
        Ray t = ray;
        t.tnear = static_cast<float>(seg) + kStep_m;
        add(t, m.transmission, p.base[e], 1);
    }
    if (m.mirror > 0.0) {
        const float dn = ray.dx * h.nx + ray.dy * h.ny + ray.dz * h.nz;
        const auto f = static_cast<float>(seg);
        Ray r;
        r.ox = ray.ox + f * ray.dx;
        r.oy = ray.oy + f * ray.dy;
        r.oz = ray.oz + f * ray.dz;
        r.dx = ray.dx - 2 * dn * h.nx;
        r.dy = ray.dy - 2 * dn * h.ny;
        r.dz = ray.dz - 2 * dn * h.nz;
        r.tnear = kStep_m;
        add(r, m.mirror, h.t, 2);
    }
}

// The continuations of each pulse, in the order they were made (a counting sort by pulse).
void PulseShader::index_by_pulse(std::size_t pulses, std::size_t own, PathScratch& p) const {
    p.first.assign(pulses + 1, 0);
    for (std::size_t e = own; e < p.hits.size(); ++e) p.first[p.pulse[e] + 1]++;
    p.most = 0;
    for (std::size_t i = 0; i < pulses; ++i) {
        p.most = std::max<std::size_t>(p.most, p.first[i + 1]);
        p.first[i + 1] += p.first[i];
    }
    p.order.resize(p.hits.size() - own);
    std::vector<std::uint32_t> at(p.first.begin(), p.first.end() - 1);
    for (std::size_t e = own; e < p.hits.size(); ++e)
        p.order[at[p.pulse[e]]++] = static_cast<std::uint32_t>(e);
}

}  // namespace mirage::render
