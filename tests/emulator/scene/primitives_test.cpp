// SPDX-License-Identifier: Apache-2.0
#include "mirage/scene/primitives.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mesh_checks.hpp"
#include "mirage/core/error.hpp"
#include "mirage/scene/mesh_ops.hpp"
#include "mirage/scene/scene.hpp"

namespace mirage::scene {
namespace {

using test::centroid;
using test::face_normal;

TEST(Primitives, plane_has_two_up_facing_triangles_and_centred_bounds) {
    const Mesh m = make_plane(4.0, 2.0, 7);
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.materials, (std::vector<std::uint32_t>{7, 7}));
    Eigen::AlignedBox3d box;
    for (const auto& v : m.vertices) box.extend(v.cast<double>());
    EXPECT_EQ(box.min(), Eigen::Vector3d(-2, -1, 0));
    EXPECT_EQ(box.max(), Eigen::Vector3d(2, 1, 0));
    for (std::size_t t = 0; t < 2; ++t) {
        const Eigen::Vector3d n = face_normal(m, t);
        EXPECT_GT(n.z(), 0);
        EXPECT_DOUBLE_EQ(n.norm() / 2, 4.0);  // each half of the 8 m² plane
    }
}

TEST(Primitives, box_has_twelve_outward_triangles_closing_the_volume) {
    const Mesh m = make_box({2.0, 4.0, 6.0}, 0);
    ASSERT_EQ(m.triangles.size(), 12u);
    ASSERT_EQ(m.vertices.size(), 8u);
    Eigen::AlignedBox3d box;
    for (const auto& v : m.vertices) box.extend(v.cast<double>());
    EXPECT_EQ(box.min(), Eigen::Vector3d(-1, -2, -3));
    EXPECT_EQ(box.max(), Eigen::Vector3d(1, 2, 3));
    int per_axis[3][2] = {};
    for (std::size_t t = 0; t < 12; ++t) {
        const Eigen::Vector3d n = face_normal(m, t).normalized();
        const Eigen::Vector3d c = centroid(m, t);
        EXPECT_GT(n.dot(c), 0) << "triangle " << t << " faces inward";
        // Normals are axis-aligned: one component ±1.
        int axis = 0;
        n.cwiseAbs().maxCoeff(&axis);
        EXPECT_NEAR(std::abs(n[axis]), 1.0, 1e-12);
        ++per_axis[axis][n[axis] > 0 ? 1 : 0];
    }
    for (auto& a : per_axis) {
        EXPECT_EQ(a[0], 2);
        EXPECT_EQ(a[1], 2);
    }
    EXPECT_TRUE(test::is_closed_and_consistent(m));
    EXPECT_NEAR(test::signed_volume(m), 48.0, 1e-9);
}

TEST(Primitives, icosphere_has_20_times_4_to_the_n_triangles_on_the_sphere) {
    for (int n = 0; n <= 4; ++n) {
        const Mesh m = make_icosphere(2.5, n, 3);
        const std::size_t tri = 20u << (2 * n);
        EXPECT_EQ(m.triangles.size(), tri);
        EXPECT_EQ(m.vertices.size(), 10u * (1u << (2 * n)) + 2u);
        EXPECT_EQ(m.materials.size(), tri);
        for (const auto& v : m.vertices) EXPECT_NEAR(v.cast<double>().norm(), 2.5, 1e-6);
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            EXPECT_GT(face_normal(m, t).dot(centroid(m, t)), 0);
        }
        EXPECT_TRUE(test::is_closed_and_consistent(m));
    }
    // Default subdivision 4: 5120 triangles whose inscribed volume approaches 4/3 π r³.
    const Mesh m = make_icosphere(1.0, 4, 0);
    EXPECT_EQ(m.triangles.size(), 5120u);
    const double v = test::signed_volume(m);
    EXPECT_LT(v, 4.0 / 3.0 * std::numbers::pi);
    EXPECT_GT(v, 0.99 * 4.0 / 3.0 * std::numbers::pi);
}

TEST(Primitives, invalid_sizes_throw_config_errors) {
    EXPECT_THROW(make_plane(0.0, 1.0, 0), ConfigError);
    EXPECT_THROW(make_box({1.0, -1.0, 1.0}, 0), ConfigError);
    EXPECT_THROW(make_box({1.0, NAN, 1.0}, 0), ConfigError);
    EXPECT_THROW(make_icosphere(1.0, 9, 0), ConfigError);
    EXPECT_THROW(make_icosphere(-1.0, 1, 0), ConfigError);
}

TEST(MeshOps, degenerate_triangles_are_dropped_and_counted) {
    Mesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}};
    LoadStats stats;
    EXPECT_TRUE(append_triangle(m, 0, 1, 3, 0, stats));
    EXPECT_FALSE(append_triangle(m, 0, 0, 3, 0, stats));  // repeated index
    EXPECT_FALSE(append_triangle(m, 0, 1, 2, 0, stats));  // collinear: zero area
    EXPECT_EQ(m.triangles.size(), 1u);
    EXPECT_EQ(stats.degenerate_triangles_dropped, 2u);
}

TEST(MeshOps, mirroring_transform_rewinds_triangles_to_stay_outward) {
    Mesh m = make_box({1.0, 1.0, 1.0}, 0);
    Eigen::Affine3d mirror = Eigen::Affine3d::Identity();
    mirror.linear() = Eigen::Vector3d(-1, 1, 1).asDiagonal();
    mirror.translation() = Eigen::Vector3d(10, 0, 0);
    transform_mesh(m, mirror);
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        EXPECT_GT(face_normal(m, t).dot(centroid(m, t) - Eigen::Vector3d(10, 0, 0)), 0);
    }
    EXPECT_NEAR(test::signed_volume(m), 1.0, 1e-9);
}

TEST(Scene, instances_place_copies_and_extend_the_bounds) {
    Scene s;
    const std::uint32_t mat = s.add_material({});
    EXPECT_EQ(mat, 0u);
    EXPECT_EQ(s.add_material({}), 1u);
    s.add_mesh(make_plane(10.0, 10.0, mat));  // placed once (no instance)
    const std::uint32_t box = s.add_mesh(make_box({1.0, 1.0, 1.0}, mat));
    for (int i = 0; i < 5; ++i) {
        Eigen::Affine3d t = Eigen::Affine3d::Identity();
        t.translation() = Eigen::Vector3d(20.0 * i, 0, 0.5);
        s.instances.push_back({box, t});
    }
    EXPECT_EQ(s.placed_triangle_count(), 2u + 5u * 12u);
    EXPECT_EQ(s.stats.triangles, 14u);  // stored triangles, instances counted once
    const Eigen::AlignedBox3d b = s.bounds();
    EXPECT_TRUE(b.min().isApprox(Eigen::Vector3d(-5, -5, 0)));
    EXPECT_TRUE(b.max().isApprox(Eigen::Vector3d(80.5, 5, 1)));
}

TEST(Scene, add_mesh_rejects_bad_indices_and_material_counts) {
    Scene s;
    s.add_material({});
    Mesh bad_vertex = make_plane(1.0, 1.0, 0);
    bad_vertex.triangles[1][2] = 4;
    EXPECT_THROW(s.add_mesh(bad_vertex), ConfigError);
    Mesh bad_material = make_plane(1.0, 1.0, 1);  // only material 0 exists
    EXPECT_THROW(s.add_mesh(bad_material), ConfigError);
    Mesh short_materials = make_plane(1.0, 1.0, 0);
    short_materials.materials.pop_back();
    EXPECT_THROW(s.add_mesh(short_materials), ConfigError);
    EXPECT_TRUE(s.meshes.empty());
    EXPECT_TRUE(s.bounds().isEmpty());
    EXPECT_EQ(s.placed_triangle_count(), 0u);
}

}  // namespace
}  // namespace mirage::scene
