// SPDX-License-Identifier: Apache-2.0
// Geometric normals: unit, facing the ray, and carried through instance transforms with the
// inverse transpose.
#include <gtest/gtest.h>

#include "render_test_util.hpp"

namespace mirage::render::test {
namespace {

// Square [-1, 1]² in the z = 0 plane; the two triangles have opposite winding, so the
// reported normal must not depend on winding.
scene::Mesh panel() {
    scene::Mesh m;
    m.name = "panel";
    add_triangle(m, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0});  // counter-clockwise from +z
    add_triangle(m, {-1, -1, 0}, {-1, 1, 0}, {1, 1, 0});  // clockwise from +z
    m.materials.assign(1, 0);
    return m;
}

class Normals : public ::testing::TestWithParam<TraceApi> {
  protected:
    EmbreeOptions options() const {
        EmbreeOptions o;
        o.api = GetParam();
        return o;
    }
};

TEST_P(Normals, direct_mesh_normals_are_unit_and_face_the_ray_whatever_the_winding) {
    scene::Scene s;
    push_material(s, "panel");
    push_mesh(s, panel());
    const EmbreeRenderer r(s, options());
    const std::vector<Ray> rays = {
        make_ray({0.5, -0.2, 5}, {0, 0, -1}),    // from above, triangle 0
        make_ray({-0.5, 0.2, 5}, {0, 0, -1}),    // from above, triangle 1
        make_ray({0.5, -0.2, -3}, {0, 0, 1}),    // from below, triangle 0
        make_ray({-0.5, 0.2, -3}, {0.1, 0, 1}),  // from below, triangle 1, oblique
    };
    const auto h = trace(r, rays);
    const float up[4] = {1, 1, -1, -1};
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_TRUE(h[i].hit()) << i;
        EXPECT_FLOAT_EQ(h[i].nx, 0.0f);
        EXPECT_FLOAT_EQ(h[i].ny, 0.0f);
        EXPECT_FLOAT_EQ(h[i].nz, up[i]) << i;
        EXPECT_EQ(h[i].primitive, i % 2) << i;
        EXPECT_EQ(h[i].instance, kInvalidId);
    }
    EXPECT_NEAR(h[0].t, 5.0f, 1e-6f);
    EXPECT_NEAR(h[3].t, 3.0 * std::sqrt(1.01), 1e-5);
}

TEST_P(Normals, instance_rotated_90_degrees_about_x_turns_the_normal_to_y) {
    scene::Scene s;
    push_material(s, "panel");
    push_mesh(s, panel());
    scene::Instance inst;
    inst.mesh = 0;
    // R_x(90°) maps the panel's z = 0 plane onto y = 0 (z -> -y), then it moves to y = 10.
    inst.transform =
        Eigen::Translation3d(0, 10, 0) * Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitX());
    s.instances.push_back(inst);
    const EmbreeRenderer r(s, options());
    const std::vector<Ray> rays = {
        make_ray({0.3, 0, 0.2}, {0, 1, 0}),     // towards +y: sees the face whose normal is -y
        make_ray({0.3, 20, -0.2}, {0, -1, 0}),  // towards -y: normal +y
        make_ray({0.3, 5, 0.2}, {0, 0, -1}),    // the panel is no longer at z = 0: miss
    };
    const auto h = trace(r, rays);
    ASSERT_TRUE(h[0].hit());
    ASSERT_TRUE(h[1].hit());
    EXPECT_FALSE(h[2].hit());
    EXPECT_NEAR(h[0].t, 10.0f, 1e-5f);
    EXPECT_NEAR(h[1].t, 10.0f, 1e-5f);
    EXPECT_NEAR(h[0].nx, 0.0f, 1e-6f);
    EXPECT_NEAR(h[0].ny, -1.0f, 1e-6f);
    EXPECT_NEAR(h[0].nz, 0.0f, 1e-6f);
    EXPECT_NEAR(h[1].ny, 1.0f, 1e-6f);
    EXPECT_EQ(h[0].instance, 0u);
    EXPECT_EQ(h[0].mesh, 0u);
    EXPECT_EQ(h[0].material, 0u);
}

TEST_P(Normals, non_uniform_scale_uses_the_inverse_transpose) {
    scene::Scene s;
    push_material(s, "panel");
    scene::Mesh tilted;
    tilted.name = "tilted";
    // Plane x + z = 0 locally (normal (1, 0, 1)/√2).
    add_triangle(tilted, {-1, -1, 1}, {1, -1, -1}, {0, 2, 0});
    tilted.materials.assign(1, 0);
    push_mesh(s, tilted);
    scene::Instance inst;
    inst.mesh = 0;
    const Eigen::Affine3d xf = Eigen::Translation3d(2, -1, 3) *
                               Eigen::AngleAxisd(0.8, Eigen::Vector3d(0.3, 1, -0.5).normalized()) *
                               Eigen::Scaling(4.0, 1.0, 0.5);
    inst.transform = xf;
    s.instances.push_back(inst);
    const EmbreeRenderer r(s, options());
    const BruteForceRenderer brute(s);
    // Exact world normal: inverse transpose of the linear part applied to the local normal.
    const Eigen::Vector3d local_n = Eigen::Vector3d(1, 0, 1).normalized();
    const Eigen::Vector3d world_n = (xf.linear().inverse().transpose() * local_n).normalized();
    // A plain rotation of the local normal would be wrong under the scaling:
    const Eigen::Vector3d naive = (xf.linear() * local_n).normalized();
    ASSERT_LT(std::abs(world_n.dot(naive)), 0.99);

    std::mt19937_64 rng(17);
    std::vector<Ray> rays;
    const Eigen::Vector3d centre = xf * Eigen::Vector3d(0, 0, 0);
    for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3d d = random_unit(rng);
        rays.push_back(make_ray(centre - 20.0 * d, d));
    }
    const auto he = trace(r, rays);
    const auto hb = trace(brute, rays);
    int hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(he[i].hit(), hb[i].hit()) << i;
        if (!he[i].hit()) continue;
        ++hits;
        const Eigen::Vector3d n(he[i].nx, he[i].ny, he[i].nz);
        const Eigen::Vector3d d(rays[i].dx, rays[i].dy, rays[i].dz);
        EXPECT_NEAR(n.norm(), 1.0, 1e-6);
        EXPECT_LT(n.dot(d), 0.0);
        EXPECT_NEAR(std::abs(n.dot(world_n)), 1.0, 1e-6) << i;
        EXPECT_NEAR(n.dot(Eigen::Vector3d(hb[i].nx, hb[i].ny, hb[i].nz)), 1.0, 1e-6) << i;
        EXPECT_EQ(he[i].instance, 0u);
    }
    EXPECT_GT(hits, 150);
}

INSTANTIATE_TEST_SUITE_P(Api, Normals, ::testing::Values(TraceApi::Single, TraceApi::Packets),
                         [](const auto& info) {
                             return std::string(info.param == TraceApi::Single ? "single"
                                                                               : "packets");
                         });

}  // namespace
}  // namespace mirage::render::test
