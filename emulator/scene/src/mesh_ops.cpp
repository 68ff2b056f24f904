// SPDX-License-Identifier: Apache-2.0
#include "mirage/scene/mesh_ops.hpp"

#include <algorithm>

namespace mirage::scene {

bool is_degenerate(const Mesh& mesh, int a, int b, int c) {
    if (a == b || b == c || a == c) return true;
    const Eigen::Vector3d p0 = mesh.vertices[static_cast<std::size_t>(a)].cast<double>();
    const Eigen::Vector3d p1 = mesh.vertices[static_cast<std::size_t>(b)].cast<double>();
    const Eigen::Vector3d p2 = mesh.vertices[static_cast<std::size_t>(c)].cast<double>();
    const Eigen::Vector3d e1 = p1 - p0;
    const Eigen::Vector3d e2 = p2 - p0;
    const Eigen::Vector3d e3 = p2 - p1;
    const double longest2 = std::max({e1.squaredNorm(), e2.squaredNorm(), e3.squaredNorm()});
    const double cross = e1.cross(e2).norm();
    return !(cross > 1e-7 * longest2);
}

bool append_triangle(Mesh& mesh, int a, int b, int c, std::uint32_t material, LoadStats& stats) {
    if (is_degenerate(mesh, a, b, c)) {
        ++stats.degenerate_triangles_dropped;
        return false;
    }
    mesh.triangles.emplace_back(a, b, c);
    mesh.materials.push_back(material);
    return true;
}

void transform_mesh(Mesh& mesh, const Eigen::Affine3d& transform) {
    for (Eigen::Vector3f& v : mesh.vertices) {
        v = (transform * v.cast<double>()).cast<float>();
    }
    if (transform.linear().determinant() < 0) {
        for (Eigen::Vector3i& t : mesh.triangles) std::swap(t[1], t[2]);
    }
}

void append_mesh(Mesh& dst, const Mesh& src, const Eigen::Affine3d& transform) {
    const int base = static_cast<int>(dst.vertices.size());
    const bool flip = transform.linear().determinant() < 0;
    dst.vertices.reserve(dst.vertices.size() + src.vertices.size());
    for (const Eigen::Vector3f& v : src.vertices) {
        dst.vertices.push_back((transform * v.cast<double>()).cast<float>());
    }
    for (const Eigen::Vector3i& t : src.triangles) {
        dst.triangles.emplace_back(base + t[0], base + (flip ? t[2] : t[1]),
                                   base + (flip ? t[1] : t[2]));
    }
    dst.materials.insert(dst.materials.end(), src.materials.begin(), src.materials.end());
}

}  // namespace mirage::scene
