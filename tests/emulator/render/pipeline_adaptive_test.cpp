// SPDX-License-Identifier: Apache-2.0
// Adaptive footprints (docs/physics.md §2.9): on one plane the closed form against a dense
// sampled footprint; at an edge, through glass and into the sky, what the probes decide.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "mirage/render/pulse_probe.hpp"
#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

sensor::SensorModel fan_sensor(std::vector<Eigen::Vector3f> dirs, int sub_rays, bool adaptive,
                               double divergence_rad = 3e-3) {
    auto s = test_sensor(std::make_shared<FanPattern>(std::move(dirs), 1000));
    s.beam.sub_rays = sub_rays;
    s.beam.divergence_rad = divergence_rad;
    s.beam.adaptive_footprint = adaptive;
    return s;
}

// A plane at 10 and 80 m, tilted 0–80°: the adaptive footprint's range and photo-electrons
// against 331 sampled sub-rays (the footprint integral to well under its own error), beside the
// sampled 19's; each pulse traces its 7 probes only.
TEST(PipelineAdaptive, a_plane_in_closed_form_matches_a_dense_sampled_footprint) {
    double worst_r = 0, worst_p = 0, worst_r19 = 0, worst_p19 = 0;
    for (double tilt : {0.0, 30.0, 60.0, 80.0}) {
        for (double d : {10.0, 80.0}) {
            const auto scene = plane_scene(4000.0, plane_frame(d, tilt * kDeg));
            std::vector<Eigen::Vector3f> dirs;
            for (int k = -3; k <= 3; ++k) dirs.push_back(unit(1, 0.01 * k, 0.02 * k));
            const auto adaptive = render_still(scene, fan_sensor(dirs, 19, true), dirs.size());
            const auto dense = render_still(scene, fan_sensor(dirs, 331, false), dirs.size());
            const auto s19 = render_still(scene, fan_sensor(dirs, 19, false), dirs.size());
            ASSERT_EQ(adaptive.points.size(), dirs.size()) << "tilt " << tilt << " d " << d;
            ASSERT_EQ(dense.points.size(), dirs.size());
            EXPECT_EQ(adaptive.stats.rays, 7 * dirs.size()) << "tilt " << tilt << " d " << d;
            for (std::size_t k = 0; k < dirs.size(); ++k) {
                const auto& a = adaptive.points[k];
                const auto& t = dense.points[k];
                const double dr = std::abs(double(a.range_m) - t.range_m);
                const double dp = std::abs(a.n_laser / t.n_laser - 1);
                EXPECT_LT(dr, 0.2e-3) << "tilt " << tilt << " d " << d << " pulse " << k;
                EXPECT_LT(dp, 2e-5) << "tilt " << tilt << " d " << d << " pulse " << k;
                worst_r = std::max(worst_r, dr);
                worst_p = std::max(worst_p, dp);
                worst_r19 =
                    std::max(worst_r19, std::abs(double(s19.points[k].range_m) - t.range_m));
                worst_p19 = std::max(worst_p19, std::abs(s19.points[k].n_laser / t.n_laser - 1));
            }
        }
    }
    std::printf(
        "plane, tilt 0-80 deg, 10 and 80 m, against 331 sampled sub-rays: adaptive range %.4f mm, "
        "photo-electrons %.5f %% (7 rays a pulse); sampled 19: %.4f mm, %.5f %%\n",
        worst_r * 1e3, worst_p * 100, worst_r19 * 1e3, worst_p19 * 100);
}

// The closed form's spread in the waveform: σ² = σ_p² + cut·(R·tan θ_b·tan S/c)² (the tilted
// plane law for a Gaussian cut at its 1/e² radius, docs/time-resolved.md §12) within 2 %.
TEST(PipelineAdaptive, a_plane_waveform_follows_the_tilted_plane_law) {
    const double cut = (1 - 3 * std::exp(-2.0)) / (1 - std::exp(-2.0));
    double worst = 0;
    for (double tilt : {20.0, 45.0, 60.0}) {
        for (double d : {30.0, 80.0}) {
            const auto scene = plane_scene(1000.0, plane_frame(d, tilt * kDeg));
            render::EmbreeRenderer r(scene);
            const double theta_b = 10e-3;
            auto sensor = fan_sensor({unit(1, 0, 0)}, 19, true, 2 * theta_b);
            sensor.beam.pulse_width_s = 4e-9;
            sensor.detector = sensor::DetectorKind::Linear;
            render::RenderOptions o;
            o.noise = false;
            o.duration = core::Nanos(1000);
            const render::Setup setup{scene, r, sensor, core::Trajectory::fixed({}), {}, {}, o};
            const auto a = render::pulse_arrivals(setup, 0);
            ASSERT_EQ(a.size(), 3U) << "tilt " << tilt << " d " << d;
            const double spread = d * std::tan(theta_b) * std::tan(tilt * kDeg) / kC * 1e9;
            const double got = delay_variance_ns2(a), want = cut * spread * spread;
            worst = std::max(worst, std::abs(got / want - 1));
            EXPECT_NEAR(got, want, 0.02 * want) << "tilt " << tilt << " d " << d;
        }
    }
    std::printf(
        "adaptive plane footprint: delay variance against the cut-Gaussian law, worst %.3f %%\n",
        worst * 100);
}

// A footprint over the plane's edge is sampled: the adaptive render is the sampled one exactly,
// with all 19 sub-rays traced; one wholly on the plane or wholly in the sky traces its probes.
TEST(PipelineAdaptive, an_edge_is_sampled_and_the_sky_costs_the_probes) {
    const auto scene = plane_scene(1.0, plane_frame(20.0, 0.0));  // edges at y = ±0.5 m
    // 3 mrad at 20 m: a footprint 6 cm across; offsets of its centre from the edge.
    for (double off : {-0.02, -0.01, 0.0, 0.01, 0.02}) {
        const std::vector<Eigen::Vector3f> dir{unit(20, 0.5 + off, 0)};
        const auto a = render_still(scene, fan_sensor(dir, 19, true), 1);
        const auto s = render_still(scene, fan_sensor(dir, 19, false), 1);
        EXPECT_EQ(a.stats.rays, 19U) << "offset " << off;
        ASSERT_EQ(a.points.size(), s.points.size()) << "offset " << off;
        for (std::size_t k = 0; k < a.points.size(); ++k) {
            EXPECT_EQ(a.points[k].range_m, s.points[k].range_m) << "offset " << off;
            EXPECT_EQ(a.points[k].n_laser, s.points[k].n_laser) << "offset " << off;
        }
    }
    const auto inside = render_still(scene, fan_sensor({unit(20, 0.3, 0)}, 19, true), 1);
    EXPECT_EQ(inside.stats.rays, 7U);
    EXPECT_EQ(inside.points.size(), 1U);
    const auto sky = render_still(scene, fan_sensor({unit(-1, 0, 0)}, 19, true), 1);
    EXPECT_EQ(sky.stats.rays, 7U);
    EXPECT_TRUE(sky.points.empty());
    EXPECT_EQ(sky.stats.misses, 1U);
}

// A surface that transmits (a leaf, glass) continues the path: its footprint is sampled.
TEST(PipelineAdaptive, a_transmissive_surface_is_sampled) {
    auto scene = plane_scene(100.0, plane_frame(20.0, 0.0));
    scene.materials[0].transmission = 0.3;
    const std::vector<Eigen::Vector3f> dir{unit(1, 0, 0)};
    const auto a = render_still(scene, fan_sensor(dir, 19, true), 1);
    const auto s = render_still(scene, fan_sensor(dir, 19, false), 1);
    EXPECT_EQ(a.stats.rays, 19U);
    ASSERT_EQ(a.points.size(), s.points.size());
    EXPECT_EQ(a.points[0].n_laser, s.points[0].n_laser);
}

}  // namespace
}  // namespace mirage::test
