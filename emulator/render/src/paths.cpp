// SPDX-License-Identifier: Apache-2.0
// Paths beyond the first hit (docs/time-resolved.md §5): a hit on a surface that transmits or
// mirrors continues the path in rounds, each round traced as one batch, until the receiver's
// max_path_depth. Transmission goes on along the same ray; a mirror sends it along the reflected
// direction from the hit. The return trip passes the same surfaces, so each multiplies the
// path's weight by its fraction squared. Below path_energy_threshold a path goes on by Russian
// roulette with its weight raised to the threshold (unbiased).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "basis.hpp"
#include "mirage/core/rng.hpp"
#include "shading.hpp"

namespace mirage::render {
namespace {

constexpr std::uint32_t kRouletteStream = 2;  // 0: discrete returns, 1: waveform noise
constexpr float kStep_m = 1e-3f;              // past the surface just left

// A ray leaving the point f along `ray` (where it hit), one step on; its direction is set after.
Ray leaving(const Ray& ray, float f) {
    Ray r;
    r.ox = ray.ox + f * ray.dx;
    r.oy = ray.oy + f * ray.dy;
    r.oz = ray.oz + f * ray.dz;
    r.tnear = kStep_m;
    return r;
}

void aim(Ray& r, const Eigen::Vector3d& d) {
    r.dx = static_cast<float>(d.x());
    r.dy = static_cast<float>(d.y());
    r.dz = static_cast<float>(d.z());
}

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
            // (a diffuse surface continues only while the path has bounces left)
            if (!continues(h) ||
                (!scene_.materials[h.material].continues() && p.bounces[k] >= bounces_))
                continue;
            if (depth >= sensor_.receiver.max_path_depth) {
                stats.paths_cut++;
                continue;
            }
            spawn(g.first,
                  {p.rays[k], h, p.weight[k], p.base[k], p.sub[k], p.code[k], p.pulse[k], p.open[k],
                   p.bounces[k]},
                  p, stats);
        }
    }
    if (bounces_ > 0) next_events(g, hits, p);
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

// One continuation of parent q into the round: its ray, weight (q's times the fraction the
// surface passes on: twice for a closed path, whose light comes back the way it went; once for an
// open one, whose light reaches the receiver from its hits), path length before the ray, and code.
// Below path_energy_threshold it goes on by Russian roulette.
void PulseShader::push_continuation(std::uint64_t first_pulse, const PathParent& q, const Ray& r,
                                    double fraction, double base, std::uint32_t kind,
                                    PathScratch& p, RenderStats& stats) const {
    double w = q.weight * (q.open ? fraction : fraction * fraction);
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
    p.open.push_back(q.open);
    p.bounces.push_back(q.bounces);
}

// A parent's continuations into the round: transmitted (same ray, beyond the surface), mirrored
// (from the hit, reflected) and bounced (diffuse).
void PulseShader::spawn(std::uint64_t first_pulse, const PathParent& q, PathScratch& p,
                        RenderStats& stats) const {
    const Hit& h = q.hit;
    const Ray& ray = q.ray;
    const scene::Material& m = scene_.materials[h.material];
    const double seg = h.t - q.base;  // along the parent's own ray
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
        push_continuation(first_pulse, q, t, tau, q.base, 1, p, stats);
    }
    if (mirror > 0.0) {
        const float dn = ray.dx * h.nx + ray.dy * h.ny + ray.dz * h.nz;
        Ray r = leaving(ray, static_cast<float>(seg));
        r.dx = ray.dx - 2 * dn * h.nx;
        r.dy = ray.dy - 2 * dn * h.ny;
        r.dz = ray.dz - 2 * dn * h.nz;
        push_continuation(first_pulse, q, r, mirror, h.t, 2, p, stats);
    }
    if (q.bounces < bounces_ && m.reflectance > 0.0) add_bounce(first_pulse, q, p, stats);
}

// A diffuse bounce (time-resolved.md §5): the path goes on from the hit in a cosine-distributed
// direction about the normal (which faces where the light came from), carrying the fraction ρ_d
// of the light that reached the hit (one way: the square root of a closed path's two-way
// weight), open from here on. The direction is drawn from the path's own code, so every thread
// count draws the same.
void PulseShader::add_bounce(std::uint64_t first_pulse, const PathParent& q, PathScratch& p,
                             RenderStats& stats) const {
    const Hit& h = q.hit;
    const Ray& ray = q.ray;
    PathParent open = q;
    open.weight = q.open ? q.weight : std::sqrt(q.weight);
    open.open = 1;
    open.bounces = static_cast<std::uint8_t>(q.bounces + 1);
    core::PulseRng rng(opt_.seed ^ (q.code * 3u), first_pulse + q.pulse, kBounceStream);
    const double u1 = rng.uniform(), u2 = rng.uniform();
    const double r = std::sqrt(u1), phi = 2.0 * std::numbers::pi * u2;
    const Eigen::Vector3d n(h.nx, h.ny, h.nz);
    Eigen::Vector3d a, b;
    orthonormal_basis(n, a, b);
    const Eigen::Vector3d d =
        r * std::cos(phi) * a + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1.0 - u1)) * n;
    Ray out = leaving(ray, static_cast<float>(h.t - q.base));
    aim(out, d);
    push_continuation(first_pulse, open, out, scene_.materials[h.material].reflectance, h.t, 0, p,
                      stats);
}

// Each open path's hit seen from the receiver: inside the pixel's field of view about its axis,
// on the side its light arrived from, with nothing between (shadow rays traced as one batch).
// Its cos θ_r/R² goes to p.nee and its hit's range becomes half the whole path, out and back,
// so both detectors place its light at the path's delay.
void PulseShader::next_events(const RayBatch& g, std::vector<Hit>& hits, PathScratch& p) const {
    p.nee.assign(p.rays.size(), -1.0);
    p.shadow.clear();
    p.shadow_of.clear();
    p.shadow_term.clear();
    for (std::size_t k = 0; k < p.rays.size(); ++k) {
        if (!p.open[k]) continue;
        p.nee[k] = 0.0;
        Hit& h = hits[p.own + k];
        if (!h.hit()) continue;
        const Ray& ray = p.rays[k];
        const double seg = double(h.t) - p.base[k];
        const Eigen::Vector3d x(ray.ox + seg * ray.dx, ray.oy + seg * ray.dy,
                                ray.oz + seg * ray.dz);
        const Eigen::Vector3d to_rx = g.origin_of(p.pulse[k]) - x;
        const double dist = to_rx.norm();
        const Eigen::Vector3d v = to_rx / dist;
        const double cos_r = v.x() * h.nx + v.y() * h.ny + v.z() * h.nz;
        const double cos_axis = -v.dot(g.axis_of(p.pulse[k]));
        h.t = static_cast<float>(0.5 * (double(h.t) + dist));
        if (!(cos_r > 0.0) || cos_axis < fov_cos_) continue;
        Ray s;
        s.ox = static_cast<float>(x.x());
        s.oy = static_cast<float>(x.y());
        s.oz = static_cast<float>(x.z());
        aim(s, v);
        s.tnear = kStep_m;
        s.tfar = static_cast<float>(dist) - kStep_m;
        p.shadow.push_back(s);
        p.shadow_of.push_back(static_cast<std::uint32_t>(k));
        p.shadow_term.push_back(cos_r / (dist * dist));
    }
    p.blocked.resize(p.shadow.size());
    renderer_.intersect(p.shadow, p.blocked);
    for (std::size_t j = 0; j < p.shadow.size(); ++j)
        if (!p.blocked[j].hit()) p.nee[p.shadow_of[j]] = p.shadow_term[j];
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
