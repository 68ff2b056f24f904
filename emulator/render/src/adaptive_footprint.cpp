// SPDX-License-Identifier: Apache-2.0
// Adaptive footprints (docs/physics.md §2.9): each pulse traces a few probe sub-rays first; where
// they all land on one plane of one plain material the footprint integral has a closed form and
// the other sub-rays are not traced; elsewhere (edges, steps, several objects, glass, mirrors)
// they are, and the pulse is shaded from all its sub-rays as a sampled footprint would be.
#include <cmath>
#include <limits>

#include "shading.hpp"

namespace mirage::render {
namespace {

// Probes agree on a plane when their normals are within ~1.4 mrad of the central one and their
// hits within 1 mm + 1e-5·R of its plane (float hits on one facet are far closer).
constexpr double kNormalCos = 1.0 - 1e-6;
constexpr double kPlaneTolM = 1e-3, kPlaneTolRel = 1e-5;
// The closed form is second order in u = (sub-ray offset)·tan θ; beyond |u| = 0.1 (grazing
// incidence) its neglected terms reach 1e-4 and the footprint is sampled.
constexpr double kMaxU = 0.1;

}  // namespace

// Per axis, the mean square of the sub-ray offsets' tangents over the whole footprint (the limit
// of many sub-rays): a Gaussian e^(−2r²/w²) cut at r = E·w has ⟨r²⟩ = (w²/2)·E[x], x = 2r²/w² on
// [0, 2E²] with density e^(−x); a top-hat ⟨r²⟩ = w²/2.
double PulseShader::footprint_m2() const {
    const auto& b = sensor_.beam;
    const double w = std::tan(0.5 * b.divergence_rad);
    if (b.profile == sensor::BeamProfile::TopHat) return 0.25 * w * w;
    const double x = 2.0 * b.footprint_radius * b.footprint_radius;
    const double mean_x = (1.0 - (1.0 + x) * std::exp(-x)) / (1.0 - std::exp(-x));
    return 0.25 * w * w * mean_x;
}

void PulseShader::trace(RayBatch& g, std::vector<Hit>& hits) const {
    g.spread.clear();
    for (auto& a : g.axis) a.clear();
    trace_footprints(g, hits);
    if (!env_.turbulence.on() || g.specs.empty()) return;
    wander(g, hits);
    trace_footprints(g, hits);
    if (image_cut_ && !g.axis[0].empty()) cut_by_fov(g, hits);
}

// Every ray (a sampled footprint), or the probes, then the rest of the pulses that need them.
void PulseShader::trace_footprints(RayBatch& g, std::vector<Hit>& hits) const {
    hits.resize(g.rays.size());
    g.plane.clear();
    if (probe_at_.empty()) {
        renderer_.intersect(g.rays, hits);
        g.traced = g.rays.size();
        return;
    }
    const std::size_t per = probe_at_.size() + rest_at_.size(), blocks = g.specs.size();
    g.traced = 0;
    g.block_done.assign(blocks, 0);
    trace_part(g, hits, true);
    g.plane.resize(blocks);
    for (std::size_t i = 0; i < blocks; ++i) {
        const std::uint32_t r = g.first_ray[i];
        g.plane[i] = plane_footprint(g, hits, i);
        g.block_done[r / per] = g.plane[i].kind != PlaneFootprint::kSampled;
    }
    trace_part(g, hits, false);
}

// One pass in tracing order: the probes of every pulse, or the other sub-rays of the pulses not
// done (made now); a skipped sub-ray reads as a miss (its hit's range is +inf).
void PulseShader::trace_part(RayBatch& g, std::vector<Hit>& hits, bool probes) const {
    const std::size_t per = probe_at_.size() + rest_at_.size();
    g.part_at.clear();
    for (std::size_t b = 0; b < g.block_done.size(); ++b) {
        const std::size_t r = b * per;
        if (!probes && g.block_done[b]) {
            for (const std::uint32_t s : rest_at_)
                hits[r + s].t = std::numeric_limits<float>::infinity();
            continue;
        }
        if (!probes) g.builder->complete(g, r, g.spread_of(b));
        for (const std::uint32_t s : probes ? probe_at_ : rest_at_)
            g.part_at.push_back(static_cast<std::uint32_t>(r + s));
    }
    renderer_.intersect_some(g.rays, g.part_at, hits);
    g.traced += g.part_at.size();
}

// The probes of pulse i: all missed, one plane (and its closed form), or neither. A footprint the
// turbulence spreads by k has k² times the offsets' mean square; one the pixel's wandering field
// of view may cut is sampled.
PlaneFootprint PulseShader::plane_footprint(const RayBatch& g, const std::vector<Hit>& hits,
                                            std::size_t i) const {
    const std::uint32_t r = g.first_ray[i];
    PlaneFootprint out;
    bool any = false, all = true;
    for (const std::uint32_t s : probe_at_) {
        if (hits[r + s].hit())
            any = true;
        else
            all = false;
    }
    if (!any) {
        out.kind = PlaneFootprint::kMissed;
        return out;
    }
    const Hit& c = hits[r];
    if (!all || !on_plane(g, hits, r)) return out;  // (all: the central one hit too)
    const double cos_i = incidence(g.rays[r], c);
    if (!(cos_i > 0.0)) return out;
    const double tan2 = (1.0 - cos_i * cos_i) / (cos_i * cos_i);
    const double k2 = g.spread_of(i) * g.spread_of(i), m2 = m2_ * k2;
    if (tan2 * max_offset2_ * k2 > kMaxU * kMaxU) return out;
    if (image_cut_ && !inside_fov(g, i, std::sqrt(max_offset2_ * k2))) return out;
    // Range R = R0·√(1 + s²)/(1 − u) and cos θ_i/R² ∝ (1 − u)³/(1 + s²)^(3/2) to second order in
    // the offsets (s² = a² + b², ⟨u²⟩ = m2·tan²θ, ⟨s²⟩ = 2·m2).
    const double u2 = m2 * tan2;
    out.kind = PlaneFootprint::kPlane;
    out.power_factor = 1.0 + 3.0 * u2 - 3.0 * m2;
    out.range_m = double(c.t) * (1.0 + m2 - 2.0 * u2);
    out.sigma_m = double(c.t) * std::sqrt(u2);
    return out;
}

// Whether every probe hit the central hit's material, facing the same way on the same plane, in
// the receiver's ranges, and the material neither continues the path nor has a specular lobe.
bool PulseShader::on_plane(const RayBatch& g, const std::vector<Hit>& hits, std::uint32_t r) const {
    const Hit& c = hits[r];
    const auto& rx = sensor_.receiver;
    if (continues_[std::min<std::size_t>(c.material, continues_.size() - 1)] ||
        brdf_constant_[c.material] < 0.0)
        return false;
    const Ray& rc = g.rays[r];
    const double px = rc.ox + double(c.t) * rc.dx, py = rc.oy + double(c.t) * rc.dy,
                 pz = rc.oz + double(c.t) * rc.dz;
    const double tol = kPlaneTolM + kPlaneTolRel * double(c.t);
    for (const std::uint32_t s : probe_at_) {
        const Hit& h = hits[r + s];
        const Ray& ray = g.rays[r + s];
        if (h.material != c.material || h.t < rx.min_range_m || h.t > rx.max_range_m) return false;
        if (double(h.nx) * c.nx + double(h.ny) * c.ny + double(h.nz) * c.nz < kNormalCos)
            return false;
        const double dx = ray.ox + double(h.t) * ray.dx - px,
                     dy = ray.oy + double(h.t) * ray.dy - py,
                     dz = ray.oz + double(h.t) * ray.dz - pz;
        if (std::abs(dx * c.nx + dy * c.ny + dz * c.nz) > tol) return false;
    }
    return true;
}

}  // namespace mirage::render
