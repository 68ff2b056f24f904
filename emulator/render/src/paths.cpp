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
    for (const Hit& h : hits)
        if (h.hit() && continues_[std::min(h.material, last)] != 0) return true;
    return false;
}

// A hit within the receiver's range on a surface that transmits or mirrors.
bool PulseShader::continues(const Hit& h) const {
    return h.hit() && h.t <= sensor_.receiver.max_range_m && continues_[h.material] != 0;
}

// Round 1 is the batch's own trace; its continuing hits, found pulse by pulse, start round 2.
// Each traced round's continuing hits start the next, until a path has met max_path_depth
// surfaces (then it is cut and counted).
bool PulseShader::trace_paths(const RayBatch& g, std::vector<Hit>& hits, ShadeScratch& s,
                              RenderStats& stats) const {
    if (!any_continuing(hits)) return false;
    PathScratch& p = s.path;
    p.start(hits.size());
    const auto subs =
        static_cast<std::uint32_t>(hits.size() / std::max<std::size_t>(1, g.specs.size()));
    for (std::uint32_t i = 0; i < g.specs.size(); ++i)
        for (std::uint32_t sub = 0; sub < subs; ++sub) {
            const std::uint32_t e = g.first_ray[i] + sub;
            if (continues(hits[e]))
                spawn(g.first, {g.rays[e], hits[e], 1.0, 0.0, sub, sub, i}, p, stats);
        }
    for (int depth = 2; trace_round(p, hits, stats); ++depth) {
        const std::size_t to = p.rays.size(), from = to - p.round_hits.size();
        for (std::size_t k = from; k < to; ++k) {
            const Hit& h = hits[p.own + k];
            if (!continues(h)) continue;
            if (depth >= sensor_.receiver.max_path_depth) {
                stats.paths_cut++;
                continue;
            }
            spawn(g.first, {p.rays[k], h, p.weight[k], p.base[k], p.sub[k], p.code[k], p.pulse[k]},
                  p, stats);
        }
    }
    index_by_pulse(g.specs.size(), p);
    return true;
}

// Traces the round's rays: their hits (whole path lengths) appended to `hits`, their rays to the
// continuations'. False when the round is empty.
bool PulseShader::trace_round(PathScratch& p, std::vector<Hit>& hits, RenderStats& stats) const {
    if (p.round_rays.empty()) return false;
    p.round_hits.assign(p.round_rays.size(), Hit{});
    renderer_.intersect(p.round_rays, p.round_hits);
    stats.path_segments += p.round_rays.size();
    const std::size_t k0 = p.rays.size();
    for (std::size_t k = 0; k < p.round_rays.size(); ++k) {
        Hit h = p.round_hits[k];
        if (h.hit()) h.t = static_cast<float>(p.base[k0 + k] + h.t);
        p.rays.push_back(p.round_rays[k]);
        hits.push_back(h);
    }
    p.round_rays.clear();
    return true;
}

// A parent's continuations into the round: transmitted (same ray, beyond the surface) and
// mirrored (from the hit, reflected), each with its weight, base, sub-ray, code and pulse.
void PulseShader::spawn(std::uint64_t first_pulse, const PathParent& q, PathScratch& p,
                        RenderStats& stats) const {
    const Hit& h = q.hit;
    const Ray& ray = q.ray;
    const scene::Material& m = scene_.materials[h.material];
    const double seg = h.t - q.base;  // along the parent's own ray
    const auto add = [&](const Ray& r, double fraction, double base, std::uint32_t kind) {
        double w = q.weight * fraction * fraction;
        const std::uint32_t code = q.code * 3u + kind;
        const double threshold = sensor_.receiver.path_energy_threshold;
        if (w < threshold) {
            core::PulseRng rng(opt_.seed ^ code, first_pulse + q.pulse, kRouletteStream);
            if (rng.uniform() * threshold >= w) {
                stats.paths_cut++;
                return;
            }
            w = threshold;
        }
        p.round_rays.push_back(r);
        p.weight.push_back(w);
        p.base.push_back(base);
        p.sub.push_back(q.sub);
        p.code.push_back(code);
        p.pulse.push_back(q.pulse);
    };
    double tau = m.transmission, mirror = m.mirror;
    if (m.refractive_index > 0.0) {  // glass: Fresnel at this hit's incidence (§5)
        const double cos_i = std::abs(ray.dx * h.nx + ray.dy * h.ny + ray.dz * h.nz);
        const double r = scene::face_reflectance(m.refractive_index, cos_i);
        tau = (1 - r) * (1 - r);
        mirror = 1 - tau;
    }
    if (tau > 0.0) {
        Ray t = ray;
        t.tnear = static_cast<float>(seg) + kStep_m;
        add(t, tau, q.base, 1);
    }
    if (mirror > 0.0) {
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
        add(r, mirror, h.t, 2);
    }
}

// The continuations of each pulse as entries, in the order they were made (a counting sort).
void PulseShader::index_by_pulse(std::size_t pulses, PathScratch& p) const {
    const std::size_t m = p.rays.size();
    p.first.assign(pulses + 1, 0);
    for (std::size_t k = 0; k < m; ++k) p.first[p.pulse[k] + 1]++;
    p.most = 0;
    for (std::size_t i = 0; i < pulses; ++i) {
        p.most = std::max<std::size_t>(p.most, p.first[i + 1]);
        p.first[i + 1] += p.first[i];
    }
    p.order.resize(m);
    std::vector<std::uint32_t> at(p.first.begin(), p.first.end() - 1);
    for (std::size_t k = 0; k < m; ++k)
        p.order[at[p.pulse[k]]++] = static_cast<std::uint32_t>(p.own + k);
}

}  // namespace mirage::render
