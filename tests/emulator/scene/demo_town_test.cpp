// SPDX-License-Identifier: Apache-2.0
#include "mirage/scene/demo_town.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <memory>
#include <numbers>

#include "mesh_checks.hpp"
#include "mirage/core/error.hpp"
#include "mirage/scene/loader.hpp"

namespace mirage::scene {
namespace {

// Distance to the rounded-rectangle road centreline (600 × 400 m, corner radius 60 m),
// written independently of the generator.
double road_distance(double x, double y, double a = 300, double b = 200, double r = 60) {
    const double qx = std::abs(x) - (a - r), qy = std::abs(y) - (b - r);
    const double out = std::hypot(std::max(qx, 0.0), std::max(qy, 0.0));
    return std::abs(out + std::min(std::max(qx, qy), 0.0) - r);
}

// Upward terrain normal from central differences of terrain_height.
Eigen::Vector3d demo_normal(const DemoTownOptions& opt, double x, double y) {
    const double h = 1e-4;
    const double gx = (terrain_height(opt, x + h, y) - terrain_height(opt, x - h, y)) / (2 * h);
    const double gy = (terrain_height(opt, x, y + h) - terrain_height(opt, x, y - h)) / (2 * h);
    return Eigen::Vector3d(-gx, -gy, 1).normalized();
}

std::uint64_t fnv1a(std::uint64_t h, const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
    return h;
}

std::uint64_t scene_hash(const Scene& s) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const Mesh& m : s.meshes) {
        h = fnv1a(h, m.vertices.data(), m.vertices.size() * sizeof(Eigen::Vector3f));
        h = fnv1a(h, m.triangles.data(), m.triangles.size() * sizeof(Eigen::Vector3i));
        h = fnv1a(h, m.materials.data(), m.materials.size() * sizeof(std::uint32_t));
    }
    for (const Instance& i : s.instances) {
        h = fnv1a(h, &i.mesh, sizeof i.mesh);
        h = fnv1a(h, i.transform.matrix().data(), 16 * sizeof(double));
    }
    return h;
}

class DemoTown : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        const auto t0 = std::chrono::steady_clock::now();
        town_ = std::make_unique<Scene>(make_demo_town());
        const auto ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        RecordProperty("demo_town_generation_ms", std::to_string(ms));
        RecordProperty("demo_town_placed_triangles",
                       std::to_string(town_->placed_triangle_count()));
        std::cout << "demo town: generated in " << ms << " ms, " << town_->placed_triangle_count()
                  << " placed triangles, " << town_->stats.triangles << " stored\n";
    }
    static void TearDownTestSuite() { town_.reset(); }

    static const Mesh& mesh(const std::string& name) {
        for (const Mesh& m : town_->meshes) {
            if (m.name == name) return m;
        }
        throw std::runtime_error("no mesh " + name);
    }
    static std::uint32_t mesh_index(const std::string& name) {
        return static_cast<std::uint32_t>(&mesh(name) - town_->meshes.data());
    }
    static std::vector<const Instance*> instances_of(const std::string& name) {
        std::vector<const Instance*> out;
        const std::uint32_t idx = mesh_index(name);
        for (const Instance& i : town_->instances) {
            if (i.mesh == idx) out.push_back(&i);
        }
        return out;
    }
    static const Material& material_of(const Mesh& m, std::size_t t) {
        return town_->materials[m.materials[t]];
    }

    static std::unique_ptr<Scene> town_;
    const DemoTownOptions opt_{};
};
std::unique_ptr<Scene> DemoTown::town_;

TEST_F(DemoTown, terrain_has_over_two_million_triangles_on_a_one_metre_grid) {
    const Mesh& t = mesh("terrain");
    EXPECT_EQ(t.triangles.size(), 2u * 1024u * 1024u);
    EXPECT_EQ(t.vertices.size(), 1025u * 1025u);
    EXPECT_GE(town_->placed_triangle_count(), 2'000'000u);
    EXPECT_EQ(town_->georef.epsg(), 32632);
    EXPECT_EQ(town_->georef.anchor(), Eigen::Vector3d(500000, 5000000, 200));
    const Eigen::AlignedBox3d b = town_->bounds();
    EXPECT_DOUBLE_EQ(b.min().x(), -512);
    EXPECT_DOUBLE_EQ(b.max().y(), 512);
}

TEST_F(DemoTown, terrain_vertices_are_the_height_function_with_bounded_height_and_slope) {
    const Mesh& t = mesh("terrain");
    double zmax = 0;
    for (const auto& v : t.vertices) {
        ASSERT_EQ(v.z(), static_cast<float>(terrain_height(opt_, v.x(), v.y())));
        zmax = std::max(zmax, std::abs(static_cast<double>(v.z())));
    }
    EXPECT_LE(zmax, 8.0);
    EXPECT_GT(zmax, 3.0);  // actually hilly
    const double cos15 = std::cos(15.0 * std::numbers::pi / 180.0);
    double steepest = 1;
    for (std::size_t i = 0; i < t.triangles.size(); ++i) {
        const Eigen::Vector3d n = test::face_normal(t, i);
        steepest = std::min(steepest, n.z() / n.norm());
    }
    EXPECT_GT(steepest, cos15);
    RecordProperty("terrain_max_slope_deg",
                   std::to_string(std::acos(steepest) * 180 / std::numbers::pi));
    for (std::size_t i = 0; i < t.triangles.size(); i += 9973) {
        EXPECT_EQ(material_of(t, i).classification, 2);
    }
}

TEST_F(DemoTown, road_is_a_closed_dark_strip_three_centimetres_above_the_terrain) {
    const Mesh& r = mesh("road");
    const Material& asphalt = material_of(r, 0);
    EXPECT_EQ(asphalt.classification, 11);
    EXPECT_DOUBLE_EQ(asphalt.reflectance, 0.1);
    // Loop length 4·240 + 4·140 + 2π·60 = 1897.0 m at ~1 m steps, 8 quads across.
    EXPECT_EQ(r.triangles.size(), 1897u * 16u);
    for (const auto& v : r.vertices) {
        EXPECT_NEAR(v.z() - terrain_height(opt_, v.x(), v.y()), 0.03, 1e-5);
        EXPECT_LE(road_distance(v.x(), v.y()), 4.0 + 1e-3);
    }
    EXPECT_TRUE(r.vertices.size() == 1897u * 9u);
    // The terrain mesh (linear between its 1 m grid vertices) stays below the asphalt at the
    // road's vertices and triangle centres: no terrain pokes through, no visible gap.
    const Mesh& ground = mesh("terrain");
    auto ground_z = [&](double x, double y) {
        const int n = 1025;
        const double gx = x + 512, gy = y + 512;
        const int c = static_cast<int>(std::floor(gx)), row = static_cast<int>(std::floor(gy));
        const double fx = gx - c, fy = gy - row;
        auto z = [&](int cc, int rr) {
            return static_cast<double>(ground.vertices[static_cast<std::size_t>(rr * n + cc)].z());
        };
        const double sw = z(c, row), se = z(c + 1, row), nw = z(c, row + 1), ne = z(c + 1, row + 1);
        return fx >= fy ? sw + fx * (se - sw) + fy * (ne - se)
                        : sw + fy * (nw - sw) + fx * (ne - nw);
    };
    double min_gap = 1, max_gap = 0;
    for (std::size_t i = 0; i < r.triangles.size(); ++i) {
        for (const Eigen::Vector3d& p :
             {test::centroid(r, i), test::vertex(r, r.triangles[i][0])}) {
            const double gap = p.z() - ground_z(p.x(), p.y());
            min_gap = std::min(min_gap, gap);
            max_gap = std::max(max_gap, gap);
        }
    }
    EXPECT_GT(min_gap, 0.02);
    EXPECT_LT(max_gap, 0.04);
    RecordProperty("road_above_terrain_mesh_m",
                   std::to_string(min_gap) + " .. " + std::to_string(max_gap));
    // Every edge is shared by two triangles except the two long borders: a closed ring.
    std::map<std::pair<int, int>, int> edges;
    for (const auto& t : r.triangles) {
        for (int k = 0; k < 3; ++k) {
            ++edges[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
        }
    }
    int border = 0;
    for (const auto& [e, n] : edges) border += n == 1;
    EXPECT_EQ(border, 2 * 1897);
    for (std::size_t i = 0; i < r.triangles.size(); ++i) EXPECT_GT(test::face_normal(r, i).z(), 0);
}

TEST_F(DemoTown, about_two_hundred_buildings_stand_in_the_ground_away_from_the_road) {
    const Mesh& b = mesh("buildings");
    ASSERT_EQ(b.triangles.size() % 14, 0u);  // 4 walls, 2 roof planes, 2 gables = 14
    const std::size_t count = b.triangles.size() / 14;
    RecordProperty("buildings", std::to_string(count));
    EXPECT_GE(count, 150u);
    EXPECT_LE(count, 250u);
    int below_ground = 0;
    for (const auto& v : b.vertices) {
        EXPECT_GT(road_distance(v.x(), v.y()), 4.0 + 5.0);
        const double ground = terrain_height(opt_, v.x(), v.y());
        if (v.z() < ground) {
            ++below_ground;
            EXPECT_LT(v.z(), ground - 0.49);  // the foundation, 0.5 m under the lowest corner
        } else {
            EXPECT_GT(v.z(), ground + 3.0);  // eaves and ridges
        }
    }
    // Each wall quad (4 vertices) has its two base vertices below the ground: nothing floats.
    EXPECT_EQ(below_ground, static_cast<int>(count) * 4 * 2);
    for (std::size_t i = 0; i < b.triangles.size(); ++i) {
        EXPECT_EQ(material_of(b, i).classification, 6);
    }
    for (int i = 0; i < static_cast<int>(count); ++i) {
        // Buildings are closed and wound outward (walls + roof; the floor is underground and
        // open, so test outwardness by the centroid of its 14 triangles).
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int k = 0; k < 14; ++k) c += test::centroid(b, static_cast<std::size_t>(14 * i + k));
        c /= 14;
        for (int k = 0; k < 14; ++k) {
            const auto t = static_cast<std::size_t>(14 * i + k);
            EXPECT_GT(test::face_normal(b, t).dot(test::centroid(b, t) - c), 0);
        }
    }
}

TEST_F(DemoTown, five_hundred_instanced_trees_stand_on_the_terrain) {
    const Mesh& tree = mesh("tree");
    EXPECT_GE(tree.triangles.size(), 50u);
    EXPECT_LE(tree.triangles.size(), 100u);
    const auto trees = instances_of("tree");
    EXPECT_EQ(trees.size(), 500u);
    for (std::size_t i = 0; i < tree.triangles.size(); ++i)
        EXPECT_EQ(material_of(tree, i).classification, 5);
    float trunk_bottom = 0;
    for (const auto& v : tree.vertices) trunk_bottom = std::min(trunk_bottom, v.z());
    EXPECT_LT(trunk_bottom, -0.3f);
    for (const Instance* i : trees) {
        const Eigen::Vector3d p = i->transform.translation();
        EXPECT_DOUBLE_EQ(p.z(), terrain_height(opt_, p.x(), p.y()));
        const double scale = std::cbrt(i->transform.linear().determinant());
        EXPECT_GE(scale, 0.7 - 1e-9);
        EXPECT_LE(scale, 1.3 + 1e-9);
        EXPECT_NEAR(i->transform.linear().col(2).normalized().z(), 1.0, 1e-12);  // upright
        EXPECT_GT(road_distance(p.x(), p.y()), 4.0 + 5.0);
    }
    // The trunk's lowest point is below the ground even on the steepest slope.
    const double slope = std::tan(9.0 * std::numbers::pi / 180);
    EXPECT_LT(trunk_bottom * 0.7 + 0.18 * 1.3 * slope, 0.0);
}

TEST_F(DemoTown, parked_cars_rest_on_the_terrain_beside_the_road) {
    const auto cars = instances_of("car");
    EXPECT_EQ(cars.size(), 60u);
    const Mesh& car = mesh("car");
    for (std::size_t i = 0; i < car.triangles.size(); ++i) {
        EXPECT_EQ(material_of(car, i).classification, 64);
    }
    bool specular_paint = false;
    for (std::uint32_t m : car.materials) specular_paint |= town_->materials[m].specular > 0.2;
    EXPECT_TRUE(specular_paint);
    for (const Instance* c : cars) {
        const Eigen::Vector3d p = c->transform.translation();
        EXPECT_NEAR(road_distance(p.x(), p.y()), 5.4, 1e-6);
        // Wheel contact points: within a few cm of the ground, never floating.
        for (double x : {-1.4, 1.4}) {
            for (double y : {-0.8, 0.8}) {
                const Eigen::Vector3d w = c->transform * Eigen::Vector3d(x, y, -0.03);
                const double gap = w.z() - terrain_height(opt_, w.x(), w.y());
                EXPECT_LT(gap, 0.0);
                EXPECT_GT(gap, -0.08);
            }
        }
    }
}

TEST_F(DemoTown, retroreflective_signs_face_the_road) {
    const auto signs = instances_of("sign");
    EXPECT_EQ(signs.size(), 40u);
    const Mesh& sign = mesh("sign");
    std::uint64_t retro = 0;
    for (std::size_t i = 0; i < sign.triangles.size(); ++i) {
        const Material& m = material_of(sign, i);
        EXPECT_EQ(m.classification, 64);
        retro += m.retroreflective ? 1 : 0;
    }
    EXPECT_EQ(retro, 2u);  // the front face of the plate
    // Placed retroreflective triangles in the whole town.
    std::uint64_t placed_retro = 0;
    for (const Instance& i : town_->instances) {
        for (std::uint32_t m : town_->meshes[i.mesh].materials) {
            placed_retro += town_->materials[m].retroreflective ? 1 : 0;
        }
    }
    EXPECT_GE(placed_retro, 30u);
    for (const Instance* s : signs) {
        const Eigen::Vector3d p = s->transform.translation();
        EXPECT_DOUBLE_EQ(p.z(), terrain_height(opt_, p.x(), p.y()));  // post sunk 0.4 m
        EXPECT_NEAR(road_distance(p.x(), p.y()), 7.5, 1e-6);
        // The face normal (mesh +x) is horizontal and parallel to the road (faces traffic).
        const Eigen::Vector3d n = s->transform.linear() * Eigen::Vector3d::UnitX();
        EXPECT_NEAR(n.z(), 0.0, 1e-12);
        const double eps = 0.5;
        const double along = road_distance(p.x() + eps * n.x(), p.y() + eps * n.y());
        EXPECT_NEAR(along, 7.5, 0.05);
    }
}

TEST_F(DemoTown, every_material_carries_a_las_class) {
    for (const Material& m : town_->materials) {
        SCOPED_TRACE(m.name);
        EXPECT_TRUE(m.classification == 2 || m.classification == 5 || m.classification == 6 ||
                    m.classification == 11 || (m.classification >= 64 && m.classification <= 66));
        EXPECT_GE(m.reflectance, 0.0);
        EXPECT_LE(m.reflectance + m.specular, 1.0);
    }
}

// A vehicle under a net with holes on the clear site nearest the centre: the vehicle wholly under
// the net, the net clear of the buildings (their bounding circles) and the road, no tree in it.
TEST_F(DemoTown, a_camouflaged_vehicle_stands_under_a_net_with_holes) {
    const Mesh& vehicle = mesh("camouflaged_vehicle");
    const Mesh& net = mesh("camouflage_net");
    EXPECT_EQ(vehicle.triangles.size(), 36u);
    EXPECT_EQ(net.triangles.size(), 10u);
    EXPECT_EQ(material_of(vehicle, 0).classification, 65);
    const Material& fabric = material_of(net, 0);
    EXPECT_EQ(fabric.classification, 66);
    EXPECT_EQ(fabric.transmission, 0.35);
    EXPECT_EQ(fabric.reflectance, 0.4);
    const Eigen::Vector3d at = camouflaged_vehicle_pose(opt_).position;
    std::printf("camouflaged vehicle at (%.1f, %.1f), ground %.2f m\n", at.x(), at.y(), at.z());
    EXPECT_DOUBLE_EQ(at.z(), terrain_height(opt_, at.x(), at.y()));
    double top = -1e9, net_top = -1e9;
    for (const auto& v : vehicle.vertices) {
        top = std::max(top, double(v.z()) - at.z());
        EXPECT_LT(std::hypot(v.x() - at.x(), v.y() - at.y()), 4.8);  // inside the net's top
    }
    for (const auto& v : net.vertices) {
        net_top = std::max(net_top, double(v.z()) - at.z());
        EXPECT_LT(std::hypot(v.x() - at.x(), v.y() - at.y()), 8.0);
    }
    EXPECT_NEAR(top, 2.1, 1e-5);
    EXPECT_NEAR(net_top, 3.0, 1e-5);
    EXPECT_GT(road_distance(at.x(), at.y()), 4.0 + 8.0 + 8.0);
    const Mesh& b = mesh("buildings");
    for (const auto& v : b.vertices)
        EXPECT_GT(std::hypot(v.x() - at.x(), v.y() - at.y()), 8.0 + 4.0);
    for (const Instance* i : instances_of("tree")) {
        const Eigen::Vector3d p = i->transform.translation();
        EXPECT_GT(std::hypot(p.x() - at.x(), p.y() - at.y()), 8.0);
    }
    DemoTownOptions none = opt_;
    none.camouflaged_vehicle = false;
    EXPECT_THROW(camouflaged_vehicle_pose(none), ConfigError);
}

TEST(DemoTownSeeds, same_seed_gives_identical_geometry_and_another_seed_differs) {
    DemoTownOptions small;
    small.size_m = 256;
    small.buildings = 20;
    small.trees = 60;
    small.cars = 10;
    small.signs = 8;
    const std::uint64_t a = scene_hash(make_demo_town(small));
    const std::uint64_t b = scene_hash(make_demo_town(small));
    small.seed = 2;
    const std::uint64_t c = scene_hash(make_demo_town(small));
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
    EXPECT_NE(terrain_height(small, 10, 20), terrain_height(DemoTownOptions{}, 10, 20));
    // "demo:<seed>" is the same town.
    EXPECT_EQ(scene_hash(resolve_scene("demo:2")), scene_hash(make_demo_town({.seed = 2})));
}

TEST(DemoTownSeeds, invalid_options_throw) {
    DemoTownOptions o;
    o.size_m = 10;
    EXPECT_THROW(make_demo_town(o), ConfigError);
    o = {};
    o.grid_m = 0;
    EXPECT_THROW(make_demo_town(o), ConfigError);
    o = {};
    o.trees = -1;
    EXPECT_THROW(make_demo_town(o), ConfigError);
}

TEST(DemoTrajectory, car_drives_the_right_lane_at_ten_metres_per_second) {
    const DemoTownOptions opt;
    const core::GpsTime t0{core::Nanos(1'000'000'000'000'000'000)};
    const core::Trajectory tr = demo_car_trajectory(opt, t0, core::Nanos(30'000'000'000));
    const auto& s = tr.samples();
    ASSERT_EQ(s.size(), 3001u);
    EXPECT_EQ(s[1].t - s[0].t, core::Nanos(10'000'000));
    EXPECT_EQ(tr.begin(), t0);
    // Starts mid-way along the southern straight, 2 m outside the centreline, heading east.
    EXPECT_NEAR(s[0].pose.position.x(), 0.0, 1e-9);
    EXPECT_NEAR(s[0].pose.position.y(), -202.0, 1e-9);
    for (std::size_t i = 0; i + 1 < s.size(); ++i) {
        const Eigen::Vector3d p = s[i].pose.position, q = s[i + 1].pose.position;
        const Eigen::Vector2d d = (q - p).head<2>();
        EXPECT_NEAR(d.norm() / 0.01, 10.0, 1e-3);  // chords on the 62 m arcs: −1e-6
        // Heading: body x projected on the ground follows the direction of travel.
        const Eigen::Vector3d x = s[i].pose.attitude * Eigen::Vector3d::UnitX();
        const double angle =
            std::acos(std::clamp(x.head<2>().normalized().dot(d.normalized()), -1.0, 1.0));
        EXPECT_LT(angle, 0.01) << "sample " << i;
        // Body z is the terrain normal; the platform rides 1.8 m above the road surface.
        const Eigen::Vector3d z = s[i].pose.attitude * Eigen::Vector3d::UnitZ();
        const Eigen::Vector3d n = demo_normal(opt, p.x(), p.y());
        EXPECT_LT((z - n).norm(), 1e-9);
        const Eigen::Vector3d road = p - Eigen::Vector3d(0, 0, 1.8);
        EXPECT_NEAR(road.z() - terrain_height(opt, road.x(), road.y()), 0.03, 1e-6);
        EXPECT_NEAR(road_distance(road.x(), road.y()), 2.0, 1e-6);
    }
    // 30 s at 10 m/s from the middle of the 480 m southern straight reaches its end zone.
    EXPECT_GT(s.back().pose.position.x(), 240.0);
}

TEST(DemoTrajectory, car_returns_to_its_start_after_one_lap) {
    const DemoTownOptions opt;
    const double lap_m = 4 * 240 + 4 * 140 + 2 * std::numbers::pi * 62;  // lane radius 62 m
    const auto lap = core::Nanos(static_cast<std::int64_t>(std::llround(lap_m / 10.0 * 1e9)));
    const core::Trajectory tr = demo_car_trajectory(opt, core::GpsTime{}, lap);
    EXPECT_LT((tr.samples().back().pose.position - tr.samples().front().pose.position).norm(),
              1e-6);
}

TEST(DemoTrajectory, flight_is_straight_and_level_300_m_above_the_centre_heading_east) {
    const DemoTownOptions opt;
    const core::GpsTime t0{core::Nanos(5'000'000'000)};
    const core::Trajectory tr = demo_flight_trajectory(opt, t0, core::Nanos(20'000'000'000));
    const auto& s = tr.samples();
    ASSERT_EQ(s.size(), 201u);
    const double z = terrain_height(opt, 0, 0) + 300.0;
    for (const auto& p : s) {
        EXPECT_DOUBLE_EQ(p.pose.position.z(), z);
        EXPECT_DOUBLE_EQ(p.pose.position.y(), 0.0);
        EXPECT_TRUE(p.pose.attitude.isApprox(Eigen::Quaterniond::Identity()));
    }
    EXPECT_DOUBLE_EQ(s.front().pose.position.x(), -500.0);
    EXPECT_NEAR(s[100].pose.position.x(), 0.0, 1e-9);  // over the centre half-way
    EXPECT_DOUBLE_EQ(s.back().pose.position.x(), 500.0);
    const core::Pose mid = tr.at(t0 + core::Nanos(10'050'000'000));
    EXPECT_NEAR(mid.position.x(), 2.5, 1e-6);
}

TEST(DemoTrajectory, camouflage_pass_flies_1200_m_over_the_vehicle_at_ten_metres_per_second) {
    const DemoTownOptions opt;
    const Eigen::Vector3d v = camouflaged_vehicle_pose(opt).position;
    const core::GpsTime t0{core::Nanos(5'000'000'000)};
    const core::Trajectory tr = demo_camouflage_trajectory(opt, t0, core::Nanos(2'000'000'000));
    const auto& s = tr.samples();
    ASSERT_EQ(s.size(), 21u);
    for (const auto& p : s) {
        EXPECT_DOUBLE_EQ(p.pose.position.z(), v.z() + 1200.0);
        EXPECT_DOUBLE_EQ(p.pose.position.y(), v.y());
        EXPECT_TRUE(p.pose.attitude.isApprox(Eigen::Quaterniond::Identity()));
    }
    EXPECT_DOUBLE_EQ(s.front().pose.position.x(), v.x() - 10.0);
    EXPECT_NEAR(s[10].pose.position.x(), v.x(), 1e-9);  // over the vehicle half-way
    EXPECT_DOUBLE_EQ(s.back().pose.position.x(), v.x() + 10.0);
}

}  // namespace
}  // namespace mirage::scene
