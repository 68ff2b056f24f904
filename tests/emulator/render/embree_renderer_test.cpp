// SPDX-License-Identifier: Apache-2.0
// EmbreeRenderer as a component: build statistics, input validation, errors, placement rules,
// materials and concurrent tracing.
#include <gtest/gtest.h>

#include <iostream>
#include <random>
#include <thread>

#include "mirage/core/error.hpp"
#include "render_test_util.hpp"

namespace mirage::render::test {
namespace {

double hills(double x, double y) { return 5.0 * std::sin(x / 50.0) * std::cos(y / 70.0); }

TEST(EmbreeRenderer, two_million_triangle_heightfield_reports_build_stats_and_exact_heights) {
    scene::Scene s;
    push_material(s, "ground");
    push_mesh(s, grid_mesh(1000, -500, -500, 1.0, hills));  // 1 m grid, 2 000 000 triangles
    const EmbreeRenderer r(s);  // built once: the only large build of the suite
    const EmbreeBuildStats& st = r.build_stats();
    const double per_tri = static_cast<double>(st.bvh_bytes) / static_cast<double>(st.triangles);
    std::cout << "[build] " << st.triangles
              << " triangles, MEDIUM, flags NONE: " << st.build_seconds << " s, Embree memory "
              << static_cast<double>(st.bvh_bytes) / 1e6 << " MB (" << per_tri << " B/triangle)\n";
    RecordProperty("bvh_bytes", std::to_string(st.bvh_bytes));
    RecordProperty("bytes_per_triangle", std::to_string(per_tri));
    RecordProperty("build_seconds", std::to_string(st.build_seconds));
    EXPECT_EQ(st.triangles, 2000000u);
    EXPECT_EQ(st.placed_triangles, 2000000u);
    EXPECT_GT(st.bvh_bytes, 0u);
    EXPECT_GT(st.build_seconds, 0.0);
    // Terrain-like meshes take about 70 B/triangle (docs/physics.md §4.5); allow a wide band.
    EXPECT_GT(per_tri, 20.0);
    EXPECT_LT(per_tri, 300.0);

    // Vertical rays onto grid vertices see the vertex height exactly (up to float rounding).
    std::vector<Ray> rays;
    std::vector<double> truth;
    std::mt19937_64 rng(1);
    std::uniform_int_distribution<int> cell(-499, 499);
    for (int i = 0; i < 10000; ++i) {
        const double x = cell(rng), y = cell(rng);
        rays.push_back(make_ray({x, y, 100.0}, {0, 0, -1}));
        truth.push_back(100.0 - static_cast<double>(static_cast<float>(hills(x, y))));
    }
    const auto hits = trace(r, rays);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_TRUE(hits[i].hit()) << i;
        EXPECT_NEAR(hits[i].t, truth[i], 2e-5) << i;
    }
}

// Packets of 8 and of 16 (whichever the machine traces natively; docs/physics.md §4.3) find
// the surfaces single rays find, through intersect() and intersect_some(), with a partial last
// packet; any other width is refused.
TEST(EmbreeRenderer, packets_of_8_and_16_give_the_single_rays_hits) {
    scene::Scene s;
    push_material(s, "ground");
    push_material(s, "tile");
    push_mesh(s, grid_mesh(100, -50, -50, 1.0, hills));
    scene::Mesh tile;
    add_triangle(tile, {0, 0, 0}, {4, 0, 0}, {4, 4, 0});
    add_triangle(tile, {0, 0, 0}, {4, 4, 0}, {0, 4, 0});
    tile.materials = {1};
    push_mesh(s, tile);
    for (int i = 0; i < 6; ++i)
        s.instances.push_back(
            {1, Eigen::Affine3d(Eigen::Translation3d(-40.0 + 12.0 * i, 3.0 * i - 8.0, 8.0))});
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<double> pos(-45, 45);
    std::vector<Ray> rays;
    for (int i = 0; i < 20003; ++i) {  // not a multiple of 8 or 16
        const Eigen::Vector3d o3(pos(rng), pos(rng), 20.0);
        rays.push_back(make_ray(o3, Eigen::Vector3d(pos(rng), pos(rng), -5.0) - o3));
    }
    std::vector<std::uint32_t> some;
    for (std::uint32_t i = 0; i < rays.size(); i += 3) some.push_back(i);
    EmbreeOptions single;
    single.api = TraceApi::Single;
    const auto truth = trace(EmbreeRenderer(s, single), rays);
    std::size_t hits = 0, on_tiles = 0;
    for (const Hit& h : truth) hits += h.hit(), on_tiles += h.hit() && h.instance != kInvalidId;
    EXPECT_GT(hits, 15000u);
    EXPECT_GT(on_tiles, 50u);
    for (const int width : {8, 16}) {
        EmbreeOptions o;
        o.packet_width = width;
        const EmbreeRenderer r(s, o);
        const auto all = trace(r, rays);
        std::vector<Hit> picked(rays.size());
        r.intersect_some(rays, some, picked);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(all[i].hit(), truth[i].hit()) << "width " << width << ", ray " << i;
            if (!truth[i].hit()) continue;
            ASSERT_EQ(all[i].instance, truth[i].instance) << "width " << width << ", ray " << i;
            ASSERT_EQ(all[i].primitive, truth[i].primitive) << "width " << width << ", ray " << i;
            ASSERT_NEAR(all[i].t, truth[i].t, 1e-5f * truth[i].t) << "width " << width;
        }
        for (const std::uint32_t i : some) {
            ASSERT_EQ(picked[i].primitive, all[i].primitive) << "width " << width << ", ray " << i;
            ASSERT_EQ(picked[i].t, all[i].t) << "width " << width << ", ray " << i;
        }
    }
    for (const int width : {4, 12, 32, -8}) {
        EmbreeOptions o;
        o.packet_width = width;
        EXPECT_THROW(EmbreeRenderer(s, o), ConfigError) << width;
    }
}

TEST(EmbreeRenderer, bad_meshes_and_instances_throw_config_errors_naming_the_input) {
    auto base = [] {
        scene::Scene s;
        push_material(s, "m");
        scene::Mesh m;
        m.name = "wall";
        add_triangle(m, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
        m.materials.assign(1, 0);
        push_mesh(s, m);
        return s;
    };
    auto message = [](const scene::Scene& s) -> std::string {
        try {
            EmbreeRenderer r(s);
        } catch (const ConfigError& e) {
            return e.what();
        }
        return "";
    };
    scene::Scene bad_index = base();
    bad_index.meshes[0].triangles[0][2] = 3;
    EXPECT_EQ(message(bad_index),
              "embree renderer: meshes[0] 'wall': triangle 0 uses vertex 3 of 3");
    scene::Scene negative = base();
    negative.meshes[0].triangles[0][1] = -1;
    EXPECT_NE(message(negative).find("uses vertex -1"), std::string::npos);
    scene::Scene bad_materials = base();
    add_triangle(bad_materials.meshes[0], {0, 0, 1}, {1, 0, 1}, {0, 1, 1});
    add_triangle(bad_materials.meshes[0], {0, 0, 2}, {1, 0, 2}, {0, 1, 2});
    bad_materials.meshes[0].materials = {0, 0};
    EXPECT_NE(message(bad_materials).find("2 materials for 3 triangles"), std::string::npos);
    scene::Scene bad_instance = base();
    scene::Instance inst;
    inst.mesh = 4;
    bad_instance.instances.push_back(inst);
    EXPECT_NE(message(bad_instance).find("instances[0].mesh = 4"), std::string::npos);
    scene::Scene singular = base();
    inst.mesh = 0;
    inst.transform = Eigen::Affine3d(Eigen::Scaling(1.0, 0.0, 1.0));
    singular.instances.push_back(inst);
    EXPECT_NE(message(singular).find("singular"), std::string::npos);
    EXPECT_THROW(BruteForceRenderer{bad_index}, ConfigError);
}

TEST(EmbreeRenderer, embree_device_errors_become_mirage_errors) {
    scene::Scene s;
    EmbreeOptions o;
    o.device_config = "threads=abc";
    try {
        EmbreeRenderer r(s, o);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_TRUE(std::string(e.what()).starts_with("embree: ")) << e.what();
    }
}

TEST(EmbreeRenderer, empty_scene_and_empty_meshes_miss_everything) {
    scene::Scene s;
    push_mesh(s, scene::Mesh{});  // no triangles, placed directly
    push_mesh(s, scene::Mesh{});  // no triangles, instanced
    s.instances.push_back({1, Eigen::Affine3d::Identity()});
    const EmbreeRenderer r(s);
    EXPECT_EQ(r.build_stats().triangles, 0u);
    EXPECT_EQ(r.build_stats().placed_triangles, 0u);
    const auto h = trace(r, {make_ray({0, 0, 1}, {0, 0, -1}), make_ray({0, 0, -1}, {1, 1, 1})});
    EXPECT_FALSE(h[0].hit());
    EXPECT_FALSE(h[1].hit());
    EXPECT_EQ(h[0].mesh, kInvalidId);
}

TEST(EmbreeRenderer, instanced_meshes_are_placed_only_through_their_instances) {
    scene::Scene s;
    push_material(s, "a");
    push_material(s, "b");
    push_material(s, "c");
    scene::Mesh tile;  // unit square at z = 0, per-triangle materials 1 and 2
    add_triangle(tile, {0, 0, 0}, {1, 0, 0}, {1, 1, 0});
    add_triangle(tile, {0, 0, 0}, {1, 1, 0}, {0, 1, 0});
    tile.materials = {1, 2};
    push_mesh(s, tile);
    scene::Mesh floor;  // direct, one material for all its triangles
    add_triangle(floor, {-10, -10, -5}, {10, -10, -5}, {10, 10, -5});
    add_triangle(floor, {-10, -10, -5}, {10, 10, -5}, {-10, 10, -5});
    floor.materials = {0};
    push_mesh(s, floor);
    s.instances.push_back({0, Eigen::Affine3d(Eigen::Translation3d(5, 0, 0))});
    s.instances.push_back({0, Eigen::Affine3d(Eigen::Translation3d(0, 5, 1))});
    const EmbreeRenderer r(s);
    EXPECT_EQ(r.build_stats().triangles, 4u);
    EXPECT_EQ(r.build_stats().placed_triangles, 6u);
    const auto h = trace(r, {
                                make_ray({0.7, 0.2, 3}, {0, 0, -1}),  // identity spot: floor
                                make_ray({5.7, 0.2, 3}, {0, 0, -1}),  // instance 0, triangle 0
                                make_ray({0.2, 5.7, 3}, {0, 0, -1}),  // instance 1, triangle 1
                            });
    EXPECT_EQ(h[0].mesh, 1u);
    EXPECT_EQ(h[0].instance, kInvalidId);
    EXPECT_EQ(h[0].material, 0u);
    EXPECT_NEAR(h[0].t, 8.0f, 1e-6f);
    EXPECT_EQ(h[1].mesh, 0u);
    EXPECT_EQ(h[1].instance, 0u);
    EXPECT_EQ(h[1].primitive, 0u);
    EXPECT_EQ(h[1].material, 1u);
    EXPECT_NEAR(h[1].t, 3.0f, 1e-6f);
    EXPECT_EQ(h[2].instance, 1u);
    EXPECT_EQ(h[2].primitive, 1u);
    EXPECT_EQ(h[2].material, 2u);
    EXPECT_NEAR(h[2].t, 2.0f, 1e-6f);
    // The brute-force reference agrees on every field.
    const auto b = trace(BruteForceRenderer(s),
                         {make_ray({0.7, 0.2, 3}, {0, 0, -1}), make_ray({5.7, 0.2, 3}, {0, 0, -1}),
                          make_ray({0.2, 5.7, 3}, {0, 0, -1})});
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(b[i].mesh, h[i].mesh);
        EXPECT_EQ(b[i].instance, h[i].instance);
        EXPECT_EQ(b[i].primitive, h[i].primitive);
        EXPECT_EQ(b[i].material, h[i].material);
        EXPECT_FLOAT_EQ(b[i].t, h[i].t);
    }
}

TEST(EmbreeRenderer, concurrent_tracing_from_two_threads_gives_the_sequential_answers) {
    scene::Scene s;
    push_material(s, "ground");
    push_mesh(s, grid_mesh(200, -100, -100, 1.0, hills));
    for (const TraceApi api : {TraceApi::Single, TraceApi::Packets}) {
        EmbreeOptions o;
        o.api = api;
        const EmbreeRenderer r(s, o);
        std::mt19937_64 rng(8);
        std::uniform_real_distribution<double> pos(-90, 90);
        std::vector<Ray> rays;
        for (int i = 0; i < 50000; ++i) {
            const Eigen::Vector3d o3(pos(rng), pos(rng), 30.0);
            rays.push_back(make_ray(o3, Eigen::Vector3d(pos(rng), pos(rng), 0.0) - o3));
        }
        const auto sequential = trace(r, rays);
        std::vector<Hit> a(rays.size()), b(rays.size());
        std::thread ta([&] { r.intersect(rays, a); });
        std::thread tb([&] { r.intersect(rays, b); });
        ta.join();
        tb.join();
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(a[i].t, sequential[i].t) << i;
            ASSERT_EQ(b[i].t, sequential[i].t) << i;
            ASSERT_EQ(a[i].primitive, sequential[i].primitive) << i;
            ASSERT_EQ(b[i].primitive, sequential[i].primitive) << i;
        }
    }
}

TEST(BruteForceRenderer, exact_ties_go_to_the_lowest_instance_mesh_primitive) {
    scene::Scene s;
    push_material(s, "m");
    scene::Mesh twin;  // the same triangle twice: primitive 0 must win
    add_triangle(twin, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
    add_triangle(twin, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
    push_mesh(s, twin);
    push_mesh(s, twin);  // mesh 1, instanced twice at the identity: instance 0 wins over all
    s.instances.push_back({1, Eigen::Affine3d::Identity()});
    s.instances.push_back({1, Eigen::Affine3d::Identity()});
    const auto h = trace(BruteForceRenderer(s), {make_ray({0, 0, 2}, {0, 0, -1})});
    ASSERT_TRUE(h[0].hit());
    EXPECT_EQ(h[0].instance, 0u);
    EXPECT_EQ(h[0].mesh, 1u);
    EXPECT_EQ(h[0].primitive, 0u);
    EXPECT_EQ(h[0].material, kInvalidId);  // mesh without materials
    EXPECT_FLOAT_EQ(h[0].t, 2.0f);
}

}  // namespace
}  // namespace mirage::render::test
