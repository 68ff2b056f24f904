// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Core>
#include <cmath>

namespace mirage::render {

// Two unit vectors orthogonal to unit d (and to each other), for sub-ray offsets and jitter.
// Written out so each costs one square root and one division (Eigen's normalized() divides
// per component, and these divisions dominated the per-pulse profile).
inline void orthonormal_basis(const Eigen::Vector3d& d, Eigen::Vector3d& u, Eigen::Vector3d& v) {
    if (std::abs(d.z()) < 0.9) {  // u = d × z / |d × z|
        const double inv = 1.0 / std::sqrt(d.x() * d.x() + d.y() * d.y());
        u = {d.y() * inv, -d.x() * inv, 0.0};
    } else {  // u = d × x / |d × x|
        const double inv = 1.0 / std::sqrt(d.y() * d.y() + d.z() * d.z());
        u = {0.0, d.z() * inv, -d.y() * inv};
    }
    v = d.cross(u);
}

}  // namespace mirage::render
