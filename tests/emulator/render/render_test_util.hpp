// SPDX-License-Identifier: Apache-2.0
// Shared helpers of the render tests: scene builders, ray makers, an independent double-precision
// ray/triangle analyser (for ambiguity classification) and error statistics.
#pragma once
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "error_stats.hpp"
#include "mirage/render/embree_renderer.hpp"
#include "mirage/render/renderer.hpp"
#include "mirage/scene/scene.hpp"

namespace mirage::render::test {

using mirage::test::ErrorStats;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// Scenes are built from the plain structs (push_back), independent of Scene's helpers.
inline std::uint32_t push_mesh(scene::Scene& s, scene::Mesh m) {
    s.meshes.push_back(std::move(m));
    return static_cast<std::uint32_t>(s.meshes.size() - 1);
}

inline std::uint32_t push_material(scene::Scene& s, const std::string& name) {
    scene::Material m;
    m.name = name;
    s.materials.push_back(m);
    return static_cast<std::uint32_t>(s.materials.size() - 1);
}

inline void add_triangle(scene::Mesh& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const Eigen::Vector3d& c) {
    const int base = static_cast<int>(m.vertices.size());
    m.vertices.push_back(a.cast<float>());
    m.vertices.push_back(b.cast<float>());
    m.vertices.push_back(c.cast<float>());
    m.triangles.emplace_back(base, base + 1, base + 2);
}

// Regular grid over [x0, x0 + n·cell] × [y0, y0 + n·cell], z = height(x, y), two triangles per
// cell. `offset` is added in double before rounding to float (negative control of §4.8).
template <class Height>
scene::Mesh grid_mesh(int n, double x0, double y0, double cell, Height height,
                      const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
    scene::Mesh m;
    m.name = "grid";
    m.vertices.reserve(static_cast<std::size_t>((n + 1) * (n + 1)));
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            const double x = x0 + i * cell, y = y0 + j * cell;
            m.vertices.push_back((Eigen::Vector3d(x, y, height(x, y)) + offset).cast<float>());
        }
    }
    m.triangles.reserve(static_cast<std::size_t>(2 * n * n));
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            m.triangles.emplace_back(a, b, d);
            m.triangles.emplace_back(a, d, c);
        }
    }
    m.materials.assign(1, 0);
    return m;
}

// Ray from a double origin and direction (normalised in double), rounded to float32 — the
// renderer's input format. `offset` is added to the origin in double before rounding.
inline Ray make_ray(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                    const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
    const Eigen::Vector3d u = d.normalized();
    const Eigen::Vector3d oo = o + offset;
    Ray r;
    r.ox = static_cast<float>(oo.x());
    r.oy = static_cast<float>(oo.y());
    r.oz = static_cast<float>(oo.z());
    r.dx = static_cast<float>(u.x());
    r.dy = static_cast<float>(u.y());
    r.dz = static_cast<float>(u.z());
    return r;
}

inline std::vector<Hit> trace(const Renderer& r, const std::vector<Ray>& rays) {
    std::vector<Hit> hits(rays.size());
    r.intersect(rays, hits);
    return hits;
}

// Unit vector uniform on the sphere.
inline Eigen::Vector3d random_unit(std::mt19937_64& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    Eigen::Vector3d v;
    do {
        v = Eigen::Vector3d(g(rng), g(rng), g(rng));
    } while (v.norm() < 1e-9);
    return v.normalized();
}

// Direction hitting a surface of normal n at incidence `theta` (angle to -n) and azimuth phi.
inline Eigen::Vector3d incident_direction(const Eigen::Vector3d& n, double theta, double phi) {
    const Eigen::Vector3d nn = n.normalized();
    const Eigen::Vector3d a =
        std::abs(nn.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d e1 = nn.cross(a).normalized(), e2 = nn.cross(e1);
    return (std::sin(theta) * (std::cos(phi) * e1 + std::sin(phi) * e2) - std::cos(theta) * nn)
        .normalized();
}

// A placed triangle in the local frame, in double.
struct PlacedTri {
    Eigen::Vector3d a, b, c;
    std::uint32_t instance, mesh, primitive;
    double frame_scale;  // |translation| of its instance (float rounding of the transform)
};

inline std::vector<PlacedTri> placed_triangles(const scene::Scene& s) {
    std::vector<PlacedTri> out;
    std::vector<bool> instanced(s.meshes.size(), false);
    for (const auto& in : s.instances) instanced[in.mesh] = true;
    auto place = [&](std::uint32_t m, const Eigen::Affine3d& xf, std::uint32_t inst) {
        const auto& mesh = s.meshes[m];
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            auto v = [&](int k) -> Eigen::Vector3d {
                return xf *
                       mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][k])].cast<double>();
            };
            out.push_back({v(0), v(1), v(2), inst, m, static_cast<std::uint32_t>(t),
                           xf.translation().norm()});
        }
    };
    for (std::size_t i = 0; i < s.instances.size(); ++i) {
        place(s.instances[i].mesh, s.instances[i].transform, static_cast<std::uint32_t>(i));
    }
    for (std::size_t m = 0; m < s.meshes.size(); ++m) {
        if (!instanced[m])
            place(static_cast<std::uint32_t>(m), Eigen::Affine3d::Identity(), kInvalidId);
    }
    return out;
}

inline double point_segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                     const Eigen::Vector3d& b) {
    const Eigen::Vector3d ab = b - a;
    const double l2 = ab.squaredNorm();
    const double s = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    return (p - (a + s * ab)).norm();
}

// Where a ray meets a triangle's plane: t and the signed distance from that point to the
// triangle boundary (> 0 inside, < 0 outside), both in metres.
struct PlaneHit {
    double t = kInf;
    double margin = -kInf;
    double cos_i = 0;  // cosine between the ray and the triangle's unit normal
};

// `near` = the margin below which the exact distance is computed; beyond it the cheap
// edge-line distance (a lower bound of the true distance outside) is returned.
inline PlaneHit plane_hit(const PlacedTri& tri, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                          double near = kInf) {
    PlaneHit h;
    const Eigen::Vector3d n = (tri.b - tri.a).cross(tri.c - tri.a);
    const double den = n.dot(d);
    const double n2 = n.squaredNorm();
    if (den == 0.0 || n2 == 0.0) return h;
    h.t = n.dot(tri.a - o) / den;
    const Eigen::Vector3d p = o + h.t * d;
    // Signed distances to the three edge lines (barycentric weight × height).
    const double nn = std::sqrt(n2);
    h.cos_i = den / (nn * d.norm());
    const double da = (tri.c - tri.b).cross(p - tri.b).dot(n) / (nn * (tri.c - tri.b).norm());
    const double db = (tri.a - tri.c).cross(p - tri.c).dot(n) / (nn * (tri.a - tri.c).norm());
    const double dc = (tri.b - tri.a).cross(p - tri.a).dot(n) / (nn * (tri.b - tri.a).norm());
    const double line = std::min({da, db, dc});
    if (line >= 0.0 || std::abs(line) > near) {
        h.margin = line;  // inside: exact distance to the boundary
        return h;
    }
    h.margin =
        -std::min({point_segment_distance(p, tri.a, tri.b), point_segment_distance(p, tri.b, tri.c),
                   point_segment_distance(p, tri.c, tri.a)});
    return h;
}

}  // namespace mirage::render::test
