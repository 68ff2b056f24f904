// SPDX-License-Identifier: Apache-2.0
// Turbulence on a pulse (docs/time-resolved.md §6): its beam wanders as a whole and its spot
// spreads, and the image of its return wanders in the receiver's focal plane. The sensor still
// reports the nominal direction, so the point lands where the moved beam ranged; the pixel's
// field of view, moved by the image's wander, may cut the spot.
#include <algorithm>
#include <cmath>
#include <limits>

#include "basis.hpp"
#include "mirage/core/rng.hpp"
#include "shading.hpp"

namespace mirage::render {

// Per pulse of g, at L the central ray's first range (the gate's end for a miss), the beam
// leaving through the receiver's aperture (w0 = D/2, a coaxial transceiver):
// - its sub-rays' offsets grow by k = √(1 + ΔW²/(L·w)²), ΔW² the short-term spread, w the
//   tangent of the beam's 1/e² half-angle (the spot's radius per metre);
// - with noise on, the whole beam turns by two normals of its stream 5 times
//   σ = √(⟨r_c²⟩/2)/L per axis, and the pixel's axis by two normals of its stream 7 times the
//   image wander's √⟨β²⟩ (g.axis).
void PulseShader::wander(RayBatch& g, const std::vector<Hit>& hits) const {
    const physics::Turbulence& turb = env_.turbulence;
    const auto& rx = sensor_.receiver;
    const double w0 = 0.5 * rx.aperture_diameter_m;
    const double w = std::tan(0.5 * sensor_.beam.divergence_rad);
    const std::size_t n = g.specs.size(), per_pulse = g.rays.size() / n;
    g.spread.assign(n, 1.0);
    for (auto& a : g.axis) a.assign(opt_.noise ? n : 0, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t r = g.first_ray[i];
        const Hit& h = hits[r];
        const double l = h.hit() && h.t > 0 ? double(h.t) : rx.max_range_m;
        const Eigen::Vector3d o = g.origin_of(i), d = g.direction_of(i);
        const double h1 = o.z() + l * d.z();
        const double spot = l * w;
        const double k =
            spot > 0.0 ? std::sqrt(1.0 + turb.beam_spread_m2(l, w0, o.z(), h1) / (spot * spot))
                       : 1.0;
        g.spread[i] = k;
        Eigen::Vector3d u, v;
        orthonormal_basis(d, u, v);
        Eigen::Vector3d turn = Eigen::Vector3d::Zero();
        if (opt_.noise) {
            const double sigma = std::sqrt(0.5 * turb.beam_wander_m2(l, w0, o.z(), h1)) / l;
            core::PulseRng rng(opt_.seed, g.first + i, kWanderStream);
            const double a = sigma * rng.normal(), b = sigma * rng.normal();
            turn = a * u + b * v;
            const double beta =
                std::sqrt(turb.image_wander_rad2(l, rx.aperture_diameter_m, o.z(), h1));
            core::PulseRng image(opt_.seed, g.first + i, kImageStream);
            const double ia = beta * image.normal(), ib = beta * image.normal();
            const Eigen::Vector3d axis = (d + ia * u + ib * v).normalized();
            for (int c = 0; c < 3; ++c) g.axis[std::size_t(c)][i] = axis[c];
        }
        const Eigen::Vector3d c(g.rays[r].dx, g.rays[r].dy, g.rays[r].dz);
        for (std::size_t s = 0; s < per_pulse; ++s) {
            Ray& ray = g.rays[r + s];
            const Eigen::Vector3d ds = Eigen::Vector3d(ray.dx, ray.dy, ray.dz);
            const Eigen::Vector3d out = (c + turn + k * (ds - c)).normalized();
            ray.dx = static_cast<float>(out.x());
            ray.dy = static_cast<float>(out.y());
            ray.dz = static_cast<float>(out.z());
        }
    }
}

// Whether pulse i's central ray, widened by `margin` (the tangent of its farthest sub-ray's
// offset), lies inside the pixel's field of view about its axis.
bool PulseShader::inside_fov(const RayBatch& g, std::size_t i, double margin) const {
    const Ray& c = g.rays[g.first_ray[i]];
    const Eigen::Vector3d d(c.dx, c.dy, c.dz), axis = g.axis_of(i);
    const double off = std::atan2(d.cross(axis).norm(), d.dot(axis));
    return off + std::atan(margin) <= fov_half_rad_;
}

// The pixel's field of view, moved by the image's wander, cuts the spot: a sub-ray outside it
// reads as a miss (docs/time-resolved.md §6). Planar pulses of adaptive footprints are inside.
void PulseShader::cut_by_fov(const RayBatch& g, std::vector<Hit>& hits) const {
    const std::size_t n = g.specs.size(), per = n > 0 ? g.rays.size() / n : 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!g.block_done.empty() && g.block_done[i]) continue;
        const Eigen::Vector3d axis = g.axis_of(i);
        const std::uint32_t r = g.first_ray[i];
        for (std::size_t s = 0; s < per; ++s) {
            // By the sine (|d × axis|): a field of view of microradians is below float's
            // resolution of a cosine near 1.
            const Eigen::Vector3d d(g.rays[r + s].dx, g.rays[r + s].dy, g.rays[r + s].dz);
            if (std::atan2(d.cross(axis).norm(), d.dot(axis)) > fov_half_rad_)
                hits[r + s].t = std::numeric_limits<float>::infinity();
        }
    }
}

}  // namespace mirage::render
