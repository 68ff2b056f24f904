// SPDX-License-Identifier: Apache-2.0
// A random leaf layer (docs/time-resolved.md §10): leaves of uniformly random orientation
// (G = ½) at leaf area index LAI leave a gap to the ground with probability exp(−G·LAI/cos θ) at
// zenith angle θ. A million single-ray pulses through a million leaves: within 1 %.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

// `count` equilateral leaves of side `side`, centres uniform in the slab [−h, h]² × [z0, z1],
// normals uniform on the sphere, each turned at random in its plane. Material 0: opaque leaf.
scene::Mesh leaves(std::size_t count, double side, double h, double z0, double z1) {
    std::mt19937_64 rng(20261127);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    scene::Mesh m;
    m.name = "leaves";
    const double r = side / std::sqrt(3.0);  // circumradius
    for (std::size_t k = 0; k < count; ++k) {
        const Eigen::Vector3d c(h * (2 * u(rng) - 1), h * (2 * u(rng) - 1),
                                z0 + (z1 - z0) * u(rng));
        const double cz = 2 * u(rng) - 1, phi = 2 * std::numbers::pi * u(rng);
        const double sz = std::sqrt(1 - cz * cz);
        const Eigen::Vector3d n(sz * std::cos(phi), sz * std::sin(phi), cz);
        Eigen::Vector3d a = n.unitOrthogonal(), b = n.cross(a);
        const double turn = 2 * std::numbers::pi * u(rng);
        const auto base = static_cast<int>(m.vertices.size());
        for (int v = 0; v < 3; ++v) {
            const double t = turn + v * 2 * std::numbers::pi / 3;
            m.vertices.push_back((c + r * (std::cos(t) * a + std::sin(t) * b)).cast<float>());
        }
        m.triangles.push_back({base, base + 1, base + 2});
        m.materials.push_back(0);
    }
    return m;
}

TEST(PipelineCanopy, gap_probability_of_a_random_leaf_layer_follows_beer_lambert) {
    const double lai = 1.5, side = 0.2, h = 55, z0 = 10, z1 = 14, height = 1000;
    const double leaf_area = std::sqrt(3.0) / 4 * side * side;
    const auto count = static_cast<std::size_t>(lai * (2 * h) * (2 * h) / leaf_area);
    scene::Scene scene;
    scene::Material leaf;
    leaf.reflectance = 0.4;
    scene.add_material(leaf);
    scene::Material soil;
    soil.reflectance = 0.2;
    scene.add_material(soil);
    scene.add_mesh(leaves(count, side, h, z0, z1));
    Eigen::Affine3d ground = Eigen::Affine3d::Identity();
    scene::Mesh g = quad(400.0, ground);
    g.materials = {1, 1};
    scene.add_mesh(std::move(g));

    // 1000 × 1000 directions from 1000 m up, 0.04 rad around a zenith angle of 30°: the rays
    // cross the layer 0.05 m apart over ±40 m, inside the leaves' ±55 m.
    const double theta0 = 30 * std::numbers::pi / 180;
    std::vector<Eigen::Vector3f> dirs;
    double expected = 0;
    for (int i = 0; i < 1000; ++i)
        for (int j = 0; j < 1000; ++j) {
            const double th = theta0 + 0.04 * (i / 999.0 - 0.5), az = 0.04 * (j / 999.0 - 0.5);
            const Eigen::Vector3d d(std::sin(th) * std::cos(az), std::sin(th) * std::sin(az),
                                    -std::cos(th));
            dirs.push_back(d.cast<float>());
            expected += std::exp(-0.5 * lai / std::cos(th));
        }
    expected /= 1e6;
    auto sensor = test_sensor(std::make_shared<FanPattern>(dirs, 1));
    sensor.beam.sub_rays = 1;
    sensor.receiver.max_range_m = 3000;
    render::EmbreeRenderer r(scene);
    render::RenderOptions o;
    o.noise = false;
    o.duration = core::Nanos(1'000'000);
    std::uint64_t ground_hits = 0, total = 0;
    CallbackSink sink([&](const core::PointRecord& p) {
        ++total;
        ground_hits += p.z < 1.0;
    });
    const core::Trajectory at = core::Trajectory::fixed(core::Pose{
        Eigen::Vector3d(-height * std::tan(theta0), 0, height), Eigen::Quaterniond::Identity()});
    render::render({scene, r, sensor, at, {}, {}, o}, sink);
    const double gap = double(ground_hits) / 1e6;
    std::printf(
        "%zu leaves, LAI %.2f: gap %.5f, exp(-G LAI / cos theta) %.5f (%+.3f %%), "
        "%llu points\n",
        count, lai, gap, expected, 100 * (gap / expected - 1),
        static_cast<unsigned long long>(total));
    EXPECT_GT(total, 999'990u);  // a leaf seen exactly edge-on returns nothing
    EXPECT_NEAR(gap / expected, 1.0, 0.01);
}

}  // namespace
}  // namespace mirage::test
