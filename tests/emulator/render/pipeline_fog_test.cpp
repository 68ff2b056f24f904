// SPDX-License-Identifier: Apache-2.0
// The atmosphere in the waveform (docs/time-resolved.md §6): in homogeneous fog the recorded
// backscatter follows the elastic lidar equation, d/dR ln(P·R²) = −2α; dense fog gives a
// near-range echo of its own (LAS class 18) and a hard target weakened by exp(−2αR).
#include <gtest/gtest.h>

#include <cmath>

#include "mirage/core/error.hpp"
#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

sensor::SensorModel fog_sensor() {
    auto s = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, 1000));
    s.beam.pulse_width_s = 4e-9;
    s.beam.pulse_energy_j = 1e-7;
    s.receiver.min_range_m = 1.0;
    s.receiver.max_returns = 4;
    s.detector = sensor::DetectorKind::Linear;
    s.linear.bits = 32;                 // no saturation,
    s.linear.gain_counts_per_pe = 1e3;  // and whole counts far finer than the signal
    return s;
}

struct FogRender {
    std::vector<core::PointRecord> points;
    std::vector<std::uint32_t> samples;
};

// One pulse (noise off) into `scene` through air of extinction α and lidar ratio S.
FogRender render_fog(const scene::Scene& scene, const sensor::SensorModel& sensor, double alpha,
                     double lidar_ratio, std::uint32_t window) {
    render::EmbreeRenderer r(scene);
    render::RenderOptions o;
    o.noise = false;
    o.threads = 1;
    o.duration = core::Nanos(1000);
    o.waveform_samples = window;
    physics::Environment env;
    env.atmosphere.extinction_per_m = alpha;
    env.lidar_ratio_sr = lidar_ratio;
    struct Sink : render::PointSink {
        FogRender out;
        void write(std::span<const core::PointRecord> p) override {
            out.points.insert(out.points.end(), p.begin(), p.end());
        }
        void write_recorded(std::span<const core::PointRecord> p,
                            std::span<const std::uint32_t> s) override {
            write(p);
            out.samples.assign(s.begin(), s.end());
        }
    } sink;
    render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, env, o}, sink);
    return sink.out;
}

// A small plane far off the beam: the scene needs geometry, the beam meets none.
scene::Scene empty_scene() {
    return plane_scene(1.0, plane_frame(50, 0).pretranslate(Eigen::Vector3d(0, 40, 0)));
}

TEST(PipelineFog, backscatter_in_homogeneous_fog_decays_as_exp_minus_two_alpha_r) {
    const double alpha = 0.02, s = 20;
    const auto sensor = fog_sensor();
    const FogRender got = render_fog(empty_scene(), sensor, alpha, s, 800);
    ASSERT_FALSE(got.points.empty());
    ASSERT_EQ(got.samples.size(), 800u);
    const double period_ns = 1.0 / sensor.linear.sample_rate_gsps;
    // The window's first sample: the point's echo time less its location in the window.
    const auto& p = got.points.front();
    EXPECT_EQ(p.classification, 18);
    const double first_ns = 2 * p.range_m / kC * 1e9 - p.wave_location_ps * 1e-3;
    // Least-squares slope of ln(n·R²) against R over 10–80 m, n from the recorded counts.
    double sx = 0, sy = 0, sxx = 0, sxy = 0, m = 0;
    for (std::size_t j = 0; j < got.samples.size(); ++j) {
        const double r = 0.5 * kC * (first_ns + double(j) * period_ns) * 1e-9;
        if (r < 10 || r > 80) continue;
        const double n =
            (got.samples[j] - sensor.linear.offset_counts) / sensor.linear.gain_counts_per_pe;
        ASSERT_GT(n, 0.0) << r;
        const double y = std::log(n * r * r);
        sx += r, sy += y, sxx += r * r, sxy += r * y, m += 1;
    }
    const double slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
    std::printf("fog alpha %.3f /m: d/dR ln(P R^2) = %.5f /m against -2 alpha = %.5f (%+.3f %%)\n",
                alpha, slope, -2 * alpha, 100 * (slope / (-2 * alpha) - 1));
    EXPECT_NEAR(slope / (-2 * alpha), 1.0, 0.02);
}

// Dense fog (α = 0.03 /m) before a wall at 40 m: the nearest echo is the fog's own, near the
// sensor; the wall's echo peaks at exp(−2α·40) of its clear-air amplitude (the fog under the
// peak adds 0.6 %). Its energy, summed from the valley after the fog's echo, also holds the
// fog's backscatter all the way to the wall, as a real receiver's would.
TEST(PipelineFog, dense_fog_gives_near_range_clutter_and_a_weakened_target) {
    const double alpha = 0.03, r_wall = 40;
    const auto scene = plane_scene(200.0, plane_frame(r_wall, 0));
    const auto sensor = fog_sensor();
    const FogRender clear = render_fog(scene, sensor, 0.0, 0.0, 64);
    const FogRender fog = render_fog(scene, sensor, alpha, 20, 64);
    ASSERT_EQ(clear.points.size(), 1u);
    ASSERT_GE(fog.points.size(), 2u);
    const auto& near = fog.points.front();
    const auto& wall = fog.points.back();
    const double ratio = wall.amplitude / clear.points[0].amplitude;
    std::printf(
        "dense fog: first echo at %.2f m (class %d), wall at %.3f m with %.4f of its "
        "clear-air amplitude (%.4f of its energy), exp(-2 alpha R) = %.4f\n",
        near.range_m, near.classification, wall.range_m, ratio,
        wall.n_laser / clear.points[0].n_laser, std::exp(-2 * alpha * r_wall));
    EXPECT_EQ(near.classification, 18);
    EXPECT_LT(near.range_m, 5.0);
    EXPECT_NEAR(wall.range_m, r_wall, 0.05);
    EXPECT_EQ(wall.classification, 2);
    EXPECT_NEAR(ratio / std::exp(-2 * alpha * r_wall), 1.0, 0.02);
}

// An airborne sensor 1500 m above a plane, through air whose extinction falls as exp(−z/H)
// (α0 = 2e-4 /m at the ground, H = 1200 m): at zenith angle θ each return keeps
// exp(−2·α0·H·(1 − e^(−1500/H))/cos θ) of its energy in clear air, both detectors.
TEST(PipelineFog, slant_path_transmittance_through_an_exponential_profile) {
    const double alpha0 = 2e-4, h = 1200, height = 1500;
    scene::Scene ground;
    scene::Material m;
    m.reflectance = 0.3;
    ground.add_material(m);
    ground.add_mesh(quad(6000.0, Eigen::Affine3d::Identity()));
    render::EmbreeRenderer r(ground);
    const double zenith[] = {0.0, 30.0, 60.0};
    std::vector<Eigen::Vector3f> dirs;
    for (const double z : zenith) {
        const double t = z * std::numbers::pi / 180;
        dirs.push_back(Eigen::Vector3d(std::sin(t), 0, -std::cos(t)).cast<float>());
    }
    for (const auto kind : {sensor::DetectorKind::Discrete, sensor::DetectorKind::Linear}) {
        auto sensor = test_sensor(std::make_shared<FanPattern>(dirs, 1000));
        sensor.beam.pulse_width_s = 4e-9;
        sensor.beam.pulse_energy_j = 1e-4;  // the 60° echo well above the digitiser's threshold
        sensor.receiver.max_range_m = 5000;
        sensor.detector = kind;
        sensor.linear.bits = 32;
        const core::Trajectory at = core::Trajectory::fixed(
            core::Pose{Eigen::Vector3d(0, 0, height), Eigen::Quaterniond::Identity()});
        std::vector<core::PointRecord> got[2];
        for (int k = 0; k < 2; ++k) {
            physics::Environment env;
            env.atmosphere.extinction_per_m = k ? alpha0 : 0.0;
            env.atmosphere.scale_height_m = h;
            render::RenderOptions o;
            o.noise = false;
            o.threads = 1;
            o.duration = core::Nanos(3000);
            VectorSink sink;
            render::render({ground, r, sensor, at, {}, env, o}, sink);
            got[k] = sink.points;
        }
        ASSERT_EQ(got[0].size(), 3u);
        ASSERT_EQ(got[1].size(), 3u);
        double worst = 0;
        for (int k = 0; k < 3; ++k) {
            const double cos_t = std::cos(zenith[k] * std::numbers::pi / 180);
            const double od = alpha0 * h * (1 - std::exp(-height / h)) / cos_t;
            const double ratio = got[1][k].n_laser / got[0][k].n_laser;
            worst = std::max(worst, std::abs(ratio / std::exp(-2 * od) - 1));
        }
        std::printf("%s: slant two-way transmittance worst %.4f %% from the closed form\n",
                    kind == sensor::DetectorKind::Linear ? "waveform" : "discrete", 100 * worst);
        EXPECT_LT(worst, 0.005);
    }
}

TEST(PipelineFog, a_lidar_ratio_needs_the_waveform_detector) {
    auto sensor = fog_sensor();
    sensor.detector = sensor::DetectorKind::Discrete;
    EXPECT_THROW(render_fog(empty_scene(), sensor, 0.02, 20, 0), ConfigError);
}

}  // namespace
}  // namespace mirage::test
