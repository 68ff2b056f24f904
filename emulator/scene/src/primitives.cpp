// SPDX-License-Identifier: Apache-2.0
#include "mirage/scene/primitives.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <unordered_map>
#include <utility>

#include "mirage/core/error.hpp"

namespace mirage::scene {

namespace {

void require_positive(double v, const char* what) {
    if (!std::isfinite(v) || v <= 0) {
        throw ConfigError(std::string("scene: ") + what + " must be a positive finite number");
    }
}

// Quad (a, b, c, d) counter-clockwise seen from outside -> two triangles.
void add_quad(Mesh& m, int a, int b, int c, int d, std::uint32_t material) {
    m.triangles.emplace_back(a, b, c);
    m.triangles.emplace_back(a, c, d);
    m.materials.push_back(material);
    m.materials.push_back(material);
}

}  // namespace

Mesh make_plane(double width_m, double length_m, std::uint32_t material) {
    require_positive(width_m, "plane width");
    require_positive(length_m, "plane length");
    const auto hx = static_cast<float>(width_m / 2);
    const auto hy = static_cast<float>(length_m / 2);
    Mesh m;
    m.name = "plane";
    m.vertices = {{-hx, -hy, 0.f}, {hx, -hy, 0.f}, {hx, hy, 0.f}, {-hx, hy, 0.f}};
    add_quad(m, 0, 1, 2, 3, material);
    return m;
}

Mesh make_box(const Eigen::Vector3d& size_m, std::uint32_t material) {
    require_positive(size_m.x(), "box size x");
    require_positive(size_m.y(), "box size y");
    require_positive(size_m.z(), "box size z");
    const Eigen::Vector3f h = (size_m / 2).cast<float>();
    Mesh m;
    m.name = "box";
    // Vertex i has +x when bit 0 is set, +y for bit 1, +z for bit 2.
    for (int i = 0; i < 8; ++i) {
        m.vertices.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(),
                                (i & 4) ? h.z() : -h.z());
    }
    add_quad(m, 4, 5, 7, 6, material);  // +z
    add_quad(m, 0, 2, 3, 1, material);  // -z
    add_quad(m, 1, 3, 7, 5, material);  // +x
    add_quad(m, 0, 4, 6, 2, material);  // -x
    add_quad(m, 2, 6, 7, 3, material);  // +y
    add_quad(m, 0, 1, 5, 4, material);  // -y
    return m;
}

Mesh make_icosphere(double radius_m, int subdivisions, std::uint32_t material) {
    require_positive(radius_m, "sphere radius");
    if (subdivisions < 0 || subdivisions > 8) {
        throw ConfigError("scene: sphere subdivisions must be 0..8, got " +
                          std::to_string(subdivisions));
    }
    // Unit icosahedron: the 12 cyclic permutations of (0, ±1, ±φ), normalised below.
    const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Eigen::Vector3d> v = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
                                      {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
                                      {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
    for (auto& p : v) p.normalize();
    std::vector<std::array<int, 3>> f = {
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int s = 0; s < subdivisions; ++s) {
        std::unordered_map<std::uint64_t, int> midpoint;
        auto mid = [&](int a, int b) {
            const auto lo = static_cast<std::uint64_t>(std::min(a, b));
            const auto hi = static_cast<std::uint64_t>(std::max(a, b));
            const std::uint64_t key = (lo << 32) | hi;
            auto it = midpoint.find(key);
            if (it != midpoint.end()) return it->second;
            v.push_back(
                (v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
            const int idx = static_cast<int>(v.size() - 1);
            midpoint.emplace(key, idx);
            return idx;
        };
        std::vector<std::array<int, 3>> next;
        next.reserve(f.size() * 4);
        for (const auto& t : f) {
            const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
            next.push_back({t[0], ab, ca});
            next.push_back({t[1], bc, ab});
            next.push_back({t[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        f = std::move(next);
    }
    Mesh m;
    m.name = "sphere";
    m.vertices.reserve(v.size());
    for (const auto& p : v) m.vertices.push_back((p * radius_m).cast<float>());
    m.triangles.reserve(f.size());
    for (const auto& t : f) {
        // Wind every face outward (the normal must point away from the centre).
        const Eigen::Vector3d& a = v[static_cast<std::size_t>(t[0])];
        const Eigen::Vector3d& b = v[static_cast<std::size_t>(t[1])];
        const Eigen::Vector3d& c = v[static_cast<std::size_t>(t[2])];
        if ((b - a).cross(c - a).dot(a + b + c) >= 0) {
            m.triangles.emplace_back(t[0], t[1], t[2]);
        } else {
            m.triangles.emplace_back(t[0], t[2], t[1]);
        }
    }
    m.materials.assign(m.triangles.size(), material);
    return m;
}

}  // namespace mirage::scene
