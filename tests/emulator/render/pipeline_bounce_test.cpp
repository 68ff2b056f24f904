// SPDX-License-Identifier: Apache-2.0
// Diffuse bounces (docs/time-resolved.md §5): light that reaches the receiver after a second
// diffuse surface, against the integral of its closed-form integrand over that surface; the
// receiver's field of view and a shadowing plate remove it; thread counts do not change it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "mirage/render/pulse_probe.hpp"
#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

constexpr double kH = 10.0;  // sensor height over the ground
constexpr double kD = 1.0;   // the wall's distance from the beam
constexpr double kW = 4.0;   // the wall's side (y in ±2, z from the ground up 4 m)
constexpr double kRhoWall = 0.6;

// A frame whose z = 0 plane is x = kD, centred at (kD, 0, −kH + kW/2).
Eigen::Affine3d wall_frame() {
    Eigen::Affine3d f = Eigen::Affine3d::Identity();
    f.translate(Eigen::Vector3d(kD, 0, -kH + kW / 2));
    f.rotate(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()));
    return f;
}

// Ground (ρ 0.5) 10 m under the sensor, a wall beside the beam, and optionally a plate at
// z = −3 between the wall and the sensor (clear of the beam).
scene::Scene corner(bool plate) {
    Eigen::Affine3d g = Eigen::Affine3d::Identity();
    g.translate(Eigen::Vector3d(0, 0, -kH));
    auto s = plane_scene(200.0, g);
    scene::Material wall;
    wall.name = "wall";
    wall.reflectance = kRhoWall;
    s.add_material(wall);
    auto w = quad(kW, wall_frame());
    w.materials = {1, 1};
    s.add_mesh(w);
    if (plate) {
        Eigen::Affine3d p = Eigen::Affine3d::Identity();
        p.translate(Eigen::Vector3d(2.2, 0, -3));
        auto m = quad(4.0, p);
        m.materials = {1, 1};
        s.add_mesh(m);
    }
    return s;
}

// One ray straight down; `ifov` the receiver's full field of view (the detector area for it).
sensor::SensorModel down_sensor(double ifov_rad, int bounces) {
    auto s = test_sensor(std::make_shared<FanPattern>(
        std::vector<Eigen::Vector3f>{Eigen::Vector3f(0, 0, -1)}, 1000));
    const double d = ifov_rad * s.receiver.f_number * s.receiver.aperture_diameter_m;
    s.receiver.detector_area_m2 = std::numbers::pi / 4 * d * d;
    s.receiver.diffuse_bounces = bounces;
    s.receiver.path_energy_threshold = 0;
    return s;
}

// Over the wall (y, z): the light it sends the receiver per unit of the ground return's, and its
// mean half path: H²·(ρ_w/π)·∫ cos θ₁·cos θ₂·cos θ_r/(d²·R²) dA (time-resolved.md §5), by the
// midpoint rule.
struct WallTruth {
    double ratio, mean_range;
};
WallTruth wall_truth() {
    constexpr int n = 1000;
    const double dy = kW / n, dz = kW / n;
    double sum = 0, sum_r = 0;
    for (int i = 0; i < n; ++i) {
        const double y = -kW / 2 + (i + 0.5) * dy;
        for (int j = 0; j < n; ++j) {
            const double z = -kH + (j + 0.5) * dz;
            const double d2 = kD * kD + y * y + (z + kH) * (z + kH), d = std::sqrt(d2);
            const double r2 = kD * kD + y * y + z * z, r = std::sqrt(r2);
            const double f = ((z + kH) / d) * (kD / d) * (kD / r) / (d2 * r2) * dy * dz;
            sum += f;
            sum_r += f * 0.5 * (kH + d + r);
        }
    }
    return {kH * kH * kRhoWall / std::numbers::pi * sum, sum_r / sum};
}

// Pulses [0, n): the ground's photo-electrons (the sub-ray's own arrival) and the bounces'
// (all other arrivals), summed, and their photo-electron-weighted half path.
struct Split {
    double own = 0, bounced = 0, range = 0;
};
Split split(const scene::Scene& scene, const sensor::SensorModel& sensor, std::uint64_t n) {
    render::EmbreeRenderer r(scene);
    render::RenderOptions o;
    o.noise = false;
    o.duration = core::Nanos(static_cast<std::int64_t>(n) * 1000);
    physics::Environment env;
    env.atmosphere.extinction_per_m = 0.0;
    const render::Setup setup{scene, r, sensor, core::Trajectory::fixed({}), {}, env, o};
    Split s;
    for (std::uint64_t p = 0; p < n; ++p)
        for (const auto& a : render::pulse_arrivals(setup, p)) {
            const double range = 1e-12 * double(a.delay_ps) * physics::kSpeedOfLightMPerS / 2;
            if (a.hit == 0) {
                s.own += a.pe;
            } else {
                s.bounced += a.pe;
                s.range += a.pe * range;
            }
        }
    if (s.bounced > 0) s.range /= s.bounced;
    return s;
}

TEST(PipelineBounce, light_off_the_ground_and_a_wall_matches_the_wall_integral) {
    const WallTruth truth = wall_truth();
    const Split got = split(corner(false), down_sensor(0.8, 1), 40000);
    const double ratio = got.bounced / got.own;
    std::printf(
        "ground then wall, 40000 bounces: bounced / direct %.5f against the wall integral %.5f "
        "(%+.2f %%); mean half path %.4f m against %.4f m\n",
        ratio, truth.ratio, 100 * (ratio / truth.ratio - 1), got.range, truth.mean_range);
    EXPECT_NEAR(ratio, truth.ratio, 0.03 * truth.ratio);
    EXPECT_NEAR(got.range, truth.mean_range, 0.01 * truth.mean_range);
}

TEST(PipelineBounce, outside_the_field_of_view_or_in_shadow_nothing_comes_back) {
    const Split narrow = split(corner(false), down_sensor(0.01, 1), 2000);
    EXPECT_GT(narrow.own, 0.0);
    EXPECT_EQ(narrow.bounced, 0.0);
    const Split shaded = split(corner(true), down_sensor(0.8, 1), 2000);
    EXPECT_GT(shaded.own, 0.0);
    EXPECT_EQ(shaded.bounced, 0.0);
    const Split off = split(corner(false), down_sensor(0.8, 0), 2000);
    EXPECT_EQ(off.bounced, 0.0);
}

TEST(PipelineBounce, thread_count_changes_nothing) {
    const auto scene = corner(false);
    auto sensor = down_sensor(0.8, 2);
    sensor.receiver.max_returns = 4;
    render::EmbreeRenderer r(scene);
    std::vector<core::PointRecord> pts[2];
    for (int t : {1, 2}) {
        render::RenderOptions o;
        o.threads = t;
        o.chunk_pulses = 64;
        o.duration = core::Nanos(4000 * 1000);
        VectorSink sink;
        render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, {}, o}, sink);
        pts[t - 1] = sink.points;
    }
    ASSERT_EQ(pts[0].size(), pts[1].size());
    std::size_t later = 0;
    for (std::size_t k = 0; k < pts[0].size(); ++k) {
        EXPECT_EQ(pts[0][k].range_m, pts[1][k].range_m) << k;
        EXPECT_EQ(pts[0][k].n_laser, pts[1][k].n_laser) << k;
        later += pts[0][k].return_number > 1;
    }
    EXPECT_GT(later, 0U);  // bounced light made returns of its own
}

}  // namespace
}  // namespace mirage::test
