// SPDX-License-Identifier: Apache-2.0
// Beam wander (docs/time-resolved.md §6): turbulence moves each pulse's beam as a whole; the
// sensor still reports the nominal direction, so the point lands where the moved beam ranged.
#include <cmath>

#include "basis.hpp"
#include "mirage/core/rng.hpp"
#include "shading.hpp"

namespace mirage::render {

// Pulse i's beam turned by two normals of its stream 5 times σ = √(⟨r_c²⟩/2)/L per axis, L the
// central ray's first range (the gate's end for a miss), the beam leaving through the receiver's
// aperture (w0 = D/2, a coaxial transceiver); its sub-rays turn with it.
void PulseShader::wander(RayBatch& g, const std::vector<Hit>& hits) const {
    const physics::Turbulence& turb = env_.turbulence;
    const double w0 = 0.5 * sensor_.receiver.aperture_diameter_m;
    const std::size_t per_pulse = g.rays.size() / g.specs.size();
    for (std::size_t i = 0; i < g.specs.size(); ++i) {
        const std::uint32_t r = g.first_ray[i];
        const Hit& h = hits[r];
        const double l = h.hit() && h.t > 0 ? double(h.t) : sensor_.receiver.max_range_m;
        const Eigen::Vector3d o = g.origin_of(i), d = g.direction_of(i);
        const double sigma =
            std::sqrt(0.5 * turb.beam_wander_m2(l, w0, o.z(), o.z() + l * d.z())) / l;
        core::PulseRng rng(opt_.seed, g.first + i, kWanderStream);
        const double a = sigma * rng.normal(), b = sigma * rng.normal();
        Eigen::Vector3d u, v;
        orthonormal_basis(d, u, v);
        const Eigen::Vector3d turn = a * u + b * v;
        for (std::size_t s = 0; s < per_pulse; ++s) {
            Ray& ray = g.rays[r + s];
            const Eigen::Vector3d ds =
                (Eigen::Vector3d(ray.dx, ray.dy, ray.dz) + turn).normalized();
            ray.dx = static_cast<float>(ds.x());
            ray.dy = static_cast<float>(ds.y());
            ray.dz = static_cast<float>(ds.z());
        }
    }
}

}  // namespace mirage::render
