// SPDX-License-Identifier: Apache-2.0
// Geometry helpers shared by the scene tests.
#pragma once
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <initializer_list>
#include <map>
#include <string>
#include <utility>

#include "mirage/core/error.hpp"
#include "mirage/scene/scene.hpp"

namespace mirage::test {

// Expects a ConfigError whose message contains every fragment.
template <class F>
void expect_error(F&& f, std::initializer_list<std::string> fragments) {
    try {
        f();
        ADD_FAILURE() << "no exception";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        for (const auto& frag : fragments) {
            EXPECT_NE(msg.find(frag), std::string::npos) << "'" << frag << "' not in: " << msg;
        }
    }
}

inline Eigen::Vector3d vertex(const scene::Mesh& m, int i) {
    return m.vertices[static_cast<std::size_t>(i)].cast<double>();
}

// Geometric normal (v1 − v0) × (v2 − v0), not normalised.
inline Eigen::Vector3d face_normal(const scene::Mesh& m, std::size_t t) {
    const Eigen::Vector3i& f = m.triangles[t];
    return (vertex(m, f[1]) - vertex(m, f[0])).cross(vertex(m, f[2]) - vertex(m, f[0]));
}

inline Eigen::Vector3d centroid(const scene::Mesh& m, std::size_t t) {
    const Eigen::Vector3i& f = m.triangles[t];
    return (vertex(m, f[0]) + vertex(m, f[1]) + vertex(m, f[2])) / 3.0;
}

// A closed, consistently wound surface uses every directed edge exactly once and its reverse
// exactly once.
inline bool is_closed_and_consistent(const scene::Mesh& m) {
    std::map<std::pair<int, int>, int> directed;
    for (const auto& t : m.triangles) {
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    }
    for (const auto& [e, n] : directed) {
        if (n != 1) return false;
        auto rev = directed.find({e.second, e.first});
        if (rev == directed.end() || rev->second != 1) return false;
    }
    return true;
}

// Enclosed volume by the divergence theorem (positive when normals point outward).
inline double signed_volume(const scene::Mesh& m) {
    double v = 0;
    for (const auto& t : m.triangles) {
        v += vertex(m, t[0]).dot(vertex(m, t[1]).cross(vertex(m, t[2]))) / 6.0;
    }
    return v;
}

inline double surface_area(const scene::Mesh& m) {
    double a = 0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) a += face_normal(m, t).norm() / 2;
    return a;
}

}  // namespace mirage::test
