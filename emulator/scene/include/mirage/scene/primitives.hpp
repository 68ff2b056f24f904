// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Core>
#include <cstdint>

#include "mirage/scene/scene.hpp"

namespace mirage::scene {

// Analytic primitives in their own frame, counter-clockwise winding seen from outside (the
// geometric normal (v1 − v0) × (v2 − v0) points out). Sizes must be positive and finite;
// otherwise ConfigError("scene: ...").

// Rectangle width_m × length_m in the z = 0 plane, centred on the origin, normal +z: 2 triangles.
Mesh make_plane(double width_m, double length_m, std::uint32_t material);

// Axis-aligned box size.x × size.y × size.z centred on the origin: 8 vertices, 12 triangles.
Mesh make_box(const Eigen::Vector3d& size_m, std::uint32_t material);

// Icosphere of `radius_m` centred on the origin: an icosahedron whose faces are split in four
// `subdivisions` times (0..8), vertices pushed onto the sphere: 20·4^n triangles
// (n = 4 -> 5120), 10·4^n + 2 vertices.
Mesh make_icosphere(double radius_m, int subdivisions, std::uint32_t material);

}  // namespace mirage::scene
