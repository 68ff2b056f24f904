// SPDX-License-Identifier: Apache-2.0
// Paths beyond the first hit against closed forms (docs/time-resolved.md §5, §10): a leaf over
// the ground gives two returns whose energies follow ρ and τ, and none behind it when τ = 0; a
// glass pane passes (1 − R)² each way; a target seen in a mirror appears at its mirror image;
// both detectors agree; the path budget cuts and counts.
#include <gtest/gtest.h>

#include <cmath>

#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

using std::numbers::pi;

struct Layer {
    scene::Material material;
    Eigen::Affine3d frame;
};

// One square of side 200 m per layer, each with its own material.
scene::Scene layered(const std::vector<Layer>& layers) {
    scene::Scene s;
    for (const Layer& l : layers) {
        const std::uint32_t m = s.add_material(l.material);
        scene::Mesh q = quad(200.0, l.frame);
        q.materials = {m, m};
        s.add_mesh(std::move(q));
    }
    return s;
}

scene::Material material(double reflectance, double transmission = 0, double mirror = 0) {
    scene::Material m;
    m.reflectance = reflectance;
    m.transmission = transmission;
    m.mirror = mirror;
    return m;
}

// A beam along +x, a few directions close to it, 7 sub-rays, up to 3 returns.
sensor::SensorModel path_sensor(sensor::DetectorKind kind) {
    std::vector<Eigen::Vector3f> dirs;
    for (int k = 0; k < 10; ++k) dirs.push_back(unit(1, 0.001 * k, -0.0007 * k));
    auto s = test_sensor(std::make_shared<FanPattern>(std::move(dirs), 1000));
    s.beam.sub_rays = 7;
    s.beam.pulse_width_s = 4e-9;
    s.receiver.max_returns = 3;
    s.detector = kind;
    return s;
}

Rendered render_scene(const scene::Scene& scene, const sensor::SensorModel& sensor,
                      std::uint64_t pulses = 100) {
    return render_still(scene, sensor, pulses);
}

// Photo-electrons of the return of `pulse` nearest to `range`.
double electrons_at(const Rendered& run, std::uint64_t pulse, double range) {
    double best = 1e9, n = 0;
    for (const auto& p : run.points)
        if (p.pulse == pulse && std::abs(p.range_m - range) < best) {
            best = std::abs(p.range_m - range);
            n = p.n_laser;
        }
    return n;
}

const sensor::DetectorKind kDetectors[] = {sensor::DetectorKind::Discrete,
                                           sensor::DetectorKind::Linear};

// Leaf (ρ_l, τ) at R1 over the footprint, ground ρ_g at R2, both square to the beam: the returns'
// energies stand as E2/E1 = τ²·ρ_g·R1² / (ρ_l·R2²) (two passes through the leaf; each sub-ray's
// cos θ/R² scales both alike), and with τ = 0 nothing comes from behind the leaf.
TEST(PipelinePaths, leaf_over_ground_returns_follow_reflectance_and_transmittance) {
    const double r1 = 30, r2 = 41, rho_l = 0.3, tau = 0.45, rho_g = 0.6;
    for (const auto kind : kDetectors) {
        const auto sensor = path_sensor(kind);
        const auto scene = layered(
            {{material(rho_l, tau), plane_frame(r1, 0)}, {material(rho_g), plane_frame(r2, 0)}});
        const Rendered run = render_scene(scene, sensor);
        ASSERT_EQ(run.points.size(), 200u) << detector_name(kind);
        double worst = 0;
        const double expected = tau * tau * rho_g * r1 * r1 / (rho_l * r2 * r2);
        for (std::uint64_t k = 0; k < 100; ++k) {
            const double ratio = electrons_at(run, k, r2) / electrons_at(run, k, r1);
            worst = std::max(worst, std::abs(ratio / expected - 1));
        }
        std::printf("%s: E2/E1 worst %.4f %% from tau^2 rho_g R1^2/(rho_l R2^2) = %.5f\n",
                    detector_name(kind), 100 * worst, expected);
        EXPECT_LT(worst, 0.01) << detector_name(kind);
        const auto opaque = layered(
            {{material(rho_l, 0), plane_frame(r1, 0)}, {material(rho_g), plane_frame(r2, 0)}});
        const Rendered none = render_scene(opaque, sensor);
        EXPECT_EQ(none.points.size(), 100u) << detector_name(kind);
        for (const auto& p : none.points) ASSERT_NEAR(p.range_m, r1, 0.01) << detector_name(kind);
    }
}

// A pane of n = 1.5 in front of a wall: the wall's return is (1 − R)⁴ of the bare wall's (two
// faces each way), R = ((n − 1)/(n + 1))²: one-way (1 − R)² = 0.9216.
TEST(PipelinePaths, a_glass_pane_passes_one_minus_r_squared_each_way) {
    scene::Material glass = material(0);
    const double n = 1.5, rf = scene::face_reflectance(n);
    glass.refractive_index = n;
    glass.transmission = (1 - rf) * (1 - rf);
    glass.mirror = 1 - glass.transmission;
    for (const auto kind : kDetectors) {
        const auto sensor = path_sensor(kind);
        const Rendered bare = render_scene(layered({{material(0.5), plane_frame(35, 0)}}), sensor);
        const Rendered pane = render_scene(
            layered({{glass, plane_frame(20, 0)}, {material(0.5), plane_frame(35, 0)}}), sensor);
        ASSERT_EQ(pane.points.size(), 100u) << detector_name(kind);
        double worst = 0;
        for (std::uint64_t k = 0; k < 100; ++k) {
            const double one_way = std::sqrt(electrons_at(pane, k, 35) / electrons_at(bare, k, 35));
            worst = std::max(worst, std::abs(one_way / 0.9216 - 1));
        }
        std::printf("%s: pane one-way transmission worst %.4f %% from 0.9216\n",
                    detector_name(kind), 100 * worst);
        EXPECT_LT(worst, 0.001) << detector_name(kind);
    }
}

// The pane tilted by θ passes (1 − R(θ))² each way, R the unpolarised Fresnel reflectance
// (R_s + R_p)/2, here from the angle forms R_s = (sin(θ−θ_t)/sin(θ+θ_t))², R_p =
// (tan(θ−θ_t)/tan(θ+θ_t))², sin θ_t = sin θ/n: 0.9216 square to the beam, 0.9187 at 30°, 0.8573
// at Brewster's angle (R_p = 0), 0.6871 at 70°; what is not passed is mirrored.
TEST(PipelinePaths, a_tilted_pane_passes_what_fresnel_leaves_at_its_incidence) {
    const double n = 1.5;
    scene::Material glass = material(0);
    glass.refractive_index = n;
    glass.transmission = std::pow(1 - scene::face_reflectance(n), 2);
    glass.mirror = 1 - glass.transmission;
    const auto one_way = [&](double theta) {  // (1 − R(θ))², R from the angle forms
        if (theta < 1e-9) return std::pow(1 - scene::face_reflectance(n), 2);
        const double t = std::asin(std::sin(theta) / n);
        const double rs = std::pow(std::sin(theta - t) / std::sin(theta + t), 2);
        const double rp = std::pow(std::tan(theta - t) / std::tan(theta + t), 2);
        return std::pow(1 - 0.5 * (rs + rp), 2);
    };
    for (const auto kind : kDetectors) {
        const auto sensor = path_sensor(kind);
        const Rendered bare = render_scene(layered({{material(0.5), plane_frame(35, 0)}}), sensor);
        for (const double tilt : {0.0, pi / 6, std::atan(n), 70 * pi / 180}) {
            const Eigen::Affine3d frame = plane_frame(20, tilt);
            const Eigen::Vector3d normal = frame.linear() * Eigen::Vector3d::UnitZ();
            const Rendered pane = render_scene(
                layered({{glass, frame}, {material(0.5), plane_frame(35, 0)}}), sensor);
            double worst = 0;
            for (std::uint64_t k = 0; k < 100; ++k) {
                // Pulse k's own incidence (the fan's directions are up to 11 mrad apart).
                const Eigen::Vector3d d(1, 0.001 * double(k % 10), -0.0007 * double(k % 10));
                const double theta = std::acos(std::abs(d.normalized().dot(normal)));
                const double got = std::sqrt(electrons_at(pane, k, 35) / electrons_at(bare, k, 35));
                worst = std::max(worst, std::abs(got / one_way(theta) - 1));
            }
            std::printf("%s: pane at %4.1f deg passes %.4f one way, worst %.4f %% from Fresnel\n",
                        detector_name(kind), tilt * 180 / pi, one_way(tilt), 100 * worst);
            EXPECT_LT(worst, 0.001) << detector_name(kind) << " " << tilt;
        }
    }
}

// A mirror at 45° at 12 m turns the beam; a wall 9 m from it along the turned beam returns at
// 21 m along the original beam: the point lies at the wall's mirror image, its energy the bare
// wall's at 21 m times m².
TEST(PipelinePaths, a_target_seen_in_a_mirror_appears_at_its_mirror_image) {
    const double d1 = 12, d2 = 9, m = 0.8;
    const Eigen::Affine3d mirror_frame = plane_frame(d1, pi / 4);
    const Eigen::Vector3d n = mirror_frame.linear() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d turned = Eigen::Vector3d::UnitX() - 2 * n.x() * n;
    // The wall square to the turned beam, d2 from the mirror.
    Eigen::Affine3d wall = Eigen::Affine3d::Identity();
    wall.translate(Eigen::Vector3d(d1, 0, 0) + d2 * turned);
    wall.rotate(Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), -turned));
    for (const auto kind : kDetectors) {
        auto sensor = path_sensor(kind);
        const Rendered seen = render_scene(
            layered({{material(0, 0, m), mirror_frame}, {material(0.5), wall}}), sensor, 1);
        const Rendered direct =
            render_scene(layered({{material(0.5), plane_frame(d1 + d2, 0)}}), sensor, 1);
        ASSERT_EQ(seen.points.size(), 1u) << detector_name(kind);
        const auto& p = seen.points[0];
        std::printf("%s: ghost at (%.4f, %.4f, %.4f), range %.4f m; energy %.5f of m^2 x direct\n",
                    detector_name(kind), p.x, p.y, p.z, p.range_m,
                    p.n_laser / (m * m * direct.points.at(0).n_laser));
        EXPECT_NEAR(p.range_m, d1 + d2, 0.01) << detector_name(kind);
        EXPECT_NEAR(p.x, d1 + d2, 0.01) << detector_name(kind);
        EXPECT_NEAR(p.y, 0, 0.01) << detector_name(kind);
        EXPECT_NEAR(p.n_laser / (m * m * direct.points.at(0).n_laser), 1.0, 0.01)
            << detector_name(kind);
    }
}

// Between two facing half-mirrors a path could go on for ever: max_path_depth stops it and
// every stop is counted; depth 1 is the first hit only.
TEST(PipelinePaths, the_depth_limit_cuts_and_counts) {
    auto sensor = path_sensor(sensor::DetectorKind::Discrete);
    const auto scene = layered({{material(0.2, 0.7), plane_frame(10, 0)},
                                {material(0.2, 0.7), plane_frame(20, 0)},
                                {material(0.2, 0.7), plane_frame(30, 0)},
                                {material(0.2, 0.7), plane_frame(40, 0)}});
    sensor.receiver.path_energy_threshold = 0;
    sensor.receiver.max_path_depth = 2;
    const Rendered two = render_scene(scene, sensor);
    EXPECT_EQ(two.points.size(), 200u);
    EXPECT_EQ(two.stats.paths_cut, 100u * 7);  // every sub-ray's path stops at the second layer
    EXPECT_EQ(two.stats.path_segments, 100u * 7);
    sensor.receiver.max_path_depth = 1;
    const Rendered one = render_scene(scene, sensor);
    EXPECT_EQ(one.points.size(), 100u);
    EXPECT_EQ(one.stats.path_segments, 0u);
    sensor.receiver.max_path_depth = 8;
    const Rendered all = render_scene(scene, sensor);
    EXPECT_EQ(all.points.size(), 300u);  // three returns kept of the four layers
}

// Russian roulette below the energy threshold keeps the mean: the third layer's mean energy over
// many pulses with a threshold above every continuation's weight matches the exact render's.
TEST(PipelinePaths, roulette_keeps_the_mean_energy) {
    auto sensor = path_sensor(sensor::DetectorKind::Discrete);
    sensor.beam.sub_rays = 1;
    const auto scene = layered({{material(0.2, 0.3), plane_frame(10, 0)},
                                {material(0.2, 0.3), plane_frame(20, 0)},
                                {material(0.5), plane_frame(30, 0)}});
    sensor.receiver.path_energy_threshold = 0;
    const Rendered exact = render_scene(scene, sensor, 1);
    const double truth = electrons_at(exact, 0, 30);
    sensor.receiver.path_energy_threshold = 0.5;  // every continuation (0.09, 0.0081) plays
    const Rendered rr = render_scene(scene, sensor, 200000);
    double sum = 0;
    for (const auto& p : rr.points)
        if (std::abs(p.range_m - 30) < 0.5) sum += p.n_laser;
    const double mean = sum / 200000;  // ~3200 survivors: the mean to ±1.7 %
    std::printf("roulette: mean third-layer energy %.4f of the exact\n", mean / truth);
    EXPECT_NEAR(mean / truth, 1.0, 0.05);
    EXPECT_GT(rr.stats.paths_cut, 150000u);
}

// With noise and the roulette on, paths and their draws are keyed by pulse: one thread and two
// give the same points.
TEST(PipelinePaths, paths_are_identical_on_any_thread_count) {
    auto sensor = path_sensor(sensor::DetectorKind::Discrete);
    sensor.receiver.path_energy_threshold = 0.5;
    sensor.noise.range_sigma_m = 0.02;
    const auto scene = layered(
        {{material(0.2, 0.5, 0.2), plane_frame(10, 0.3)}, {material(0.5), plane_frame(25, -0.2)}});
    std::vector<core::PointRecord> got[2];
    for (int t = 1; t <= 2; ++t) {
        render::EmbreeRenderer r(scene);
        render::RenderOptions o;
        o.threads = t;
        o.chunk_pulses = 512;
        o.duration = core::Nanos(5000 * 1000);
        VectorSink sink;
        render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, {}, o}, sink);
        got[t - 1] = sink.points;
    }
    ASSERT_EQ(got[0].size(), got[1].size());
    ASSERT_GT(got[0].size(), 5000u);
    for (std::size_t k = 0; k < got[0].size(); ++k) {
        ASSERT_EQ(got[0][k].range_m, got[1][k].range_m) << k;
        ASSERT_EQ(got[0][k].n_laser, got[1][k].n_laser) << k;
    }
}

}  // namespace
}  // namespace mirage::test
