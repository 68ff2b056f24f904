// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <Eigen/Geometry>
#include <cstdint>

#include "mirage/scene/scene.hpp"

namespace mirage::scene {

// True when the triangle cannot be hit: a repeated vertex index or (numerically) zero area.
// "Zero area" is relative: |e1 × e2| <= 1e-7 · (longest edge)², i.e. the triangle's smallest
// angle is below ~1e-7 rad, which float32 vertices cannot resolve anyway.
bool is_degenerate(const Mesh& mesh, int a, int b, int c);

// Appends triangle (a, b, c) with `material` unless it is degenerate; a dropped triangle is
// counted in stats.degenerate_triangles_dropped. Indices must already be valid.
bool append_triangle(Mesh& mesh, int a, int b, int c, std::uint32_t material, LoadStats& stats);

// Applies an affine map to every vertex (computed in double, stored as float). A map with
// negative determinant would flip the winding, so the triangles are re-wound to keep
// outward normals outward.
void transform_mesh(Mesh& mesh, const Eigen::Affine3d& transform);

// Appends `src` transformed by `transform` to `dst` (vertices, triangles and materials).
void append_mesh(Mesh& dst, const Mesh& src,
                 const Eigen::Affine3d& transform = Eigen::Affine3d::Identity());

}  // namespace mirage::scene
