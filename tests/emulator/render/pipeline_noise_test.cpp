// SPDX-License-Identifier: Apache-2.0
// docs/physics.md eqs. (12)–(15) through the pipeline: measured σ of range noise and jitter within
// 1 % of the configured values over 1e6 pulses; void fraction within 1 % of the closed-form
// prediction.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

constexpr std::uint64_t kPulses = 1'000'000;

Eigen::Affine3d facing_plane(double d) {
    Eigen::Affine3d f = Eigen::Affine3d::Identity();
    f.translate(Eigen::Vector3d(d, 0, 0));
    f.rotate(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()));
    return f;
}

render::RenderOptions noisy() {
    render::RenderOptions o;
    o.threads = 2;
    o.seed = 42;
    o.duration = core::Nanos(static_cast<std::int64_t>(kPulses) * 1000);
    return o;
}

struct Moments {
    double sum = 0, sum2 = 0;
    std::uint64_t n = 0;
    void add(double v) {
        sum += v;
        sum2 += v * v;
        ++n;
    }
    double mean() const { return sum / double(n); }
    double sigma() const { return std::sqrt(sum2 / double(n) - mean() * mean()); }
};

TEST(PipelineNoise, range_noise_and_jitter_sigmas_within_one_percent) {
    const double d = 50.0;
    const auto scene = plane_scene(400.0, facing_plane(d));
    render::EmbreeRenderer r(scene);
    auto sensor = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, 1000));
    sensor.noise.range_sigma_m = 0.05;
    sensor.noise.jitter_sigma_rad = 1e-3;
    Moments range, ax, ay;
    CallbackSink sink([&](const core::PointRecord& p) {
        const double a_y = std::atan2(p.y, p.x), a_z = std::atan2(p.z, std::hypot(p.x, p.y));
        ax.add(a_y);
        ay.add(a_z);
        // The reported range is the noisy range along the jittered direction.
        range.add(double(p.range_m) - d);
    });
    const auto stats =
        render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, {}, noisy()}, sink);
    ASSERT_EQ(stats.points, kPulses);
    std::printf(
        "range sigma %.5f m (0.05), jitter sigma %.6f / %.6f rad (0.001), means %.2e %.2e %.2e\n",
        range.sigma(), ax.sigma(), ay.sigma(), range.mean(), ax.mean(), ay.mean());
    EXPECT_NEAR(range.sigma() / 0.05, 1.0, 0.01);
    EXPECT_NEAR(ax.sigma() / 1e-3, 1.0, 0.01);
    EXPECT_NEAR(ay.sigma() / 1e-3, 1.0, 0.01);
    EXPECT_NEAR(range.mean(), 0.0, 5 * 0.05 / 1000.0);  // 5 standard errors
}

// Jitter angles beyond 1e-2 rad leave the tangent series the batched shading uses and take the
// exact tangent: with σ = 0.02 rad most draws do. The in-plane angle is atan(tan(σ·z)) = σ·z
// exactly, the other within (σ·z)²/2 of it, so both spreads must still be σ.
TEST(PipelineNoise, large_jitter_angles_keep_their_sigma) {
    const double d = 50.0;
    const double sigma = 0.02;
    const auto scene = plane_scene(400.0, facing_plane(d));
    render::EmbreeRenderer r(scene);
    auto sensor = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, 1000));
    sensor.noise.jitter_sigma_rad = sigma;
    Moments ax, ay;
    CallbackSink sink([&](const core::PointRecord& p) {
        ax.add(std::atan2(p.y, p.x));
        ay.add(std::atan2(p.z, std::hypot(p.x, p.y)));
    });
    render::RenderOptions opt = noisy();
    opt.duration = core::Nanos(200'000 * 1000);
    const auto stats =
        render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, {}, opt}, sink);
    ASSERT_EQ(stats.points, 200'000u);
    std::printf("jitter sigma 0.02 rad: measured %.6f / %.6f rad\n", ax.sigma(), ay.sigma());
    EXPECT_NEAR(ax.sigma() / sigma, 1.0, 0.01);
    EXPECT_NEAR(ay.sigma() / sigma, 1.0, 0.01);
}

TEST(PipelineNoise, void_fraction_matches_closed_form_prediction) {
    const double d = 80.0;
    const auto scene = plane_scene(400.0, facing_plane(d), 0.2);
    render::EmbreeRenderer r(scene);
    auto sensor = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, 1000));
    sensor.beam.pulse_energy_j = 1e-8;
    sensor.receiver.threshold_gamma = 3.0;
    physics::Environment env;
    env.sun.elevation_rad = 0.7;
    env.sun.irradiance_w_m2_um = 700.0;
    // Choose σ₁ so the void threshold sits at |z| = 1 (prediction ≈ 31.7 %).
    physics::Radiometry unit_noise(
        [&] {
            auto b = sensor.beam;
            return b;
        }(),
        [&] {
            auto rx = sensor.receiver;
            rx.noise_irradiance_sigma = 1.0;
            return rx;
        }(),
        env);
    const double n_laser =
        unit_noise.laser_electrons(unit_noise.closed_form_lambertian_w(d, 0.2, 1.0));
    const double cos_sun = std::abs(env.sun.to_sun_enu().dot(Eigen::Vector3d(1, 0, 0)));
    const double n_other = unit_noise.background_electrons(d, 0.2 / std::numbers::pi, cos_sun);
    const double rhs = std::pow(n_laser / 3.0, 2) - n_laser - n_other;
    ASSERT_GT(rhs, 0.0) << "signal too weak for the test: n_laser " << n_laser;
    sensor.receiver.noise_irradiance_sigma = std::sqrt(rhs) / unit_noise.noise_floor_electrons();
    const physics::Radiometry rad(sensor.beam, sensor.receiver, env);
    const double predicted = rad.void_probability(n_laser, n_other);
    std::uint64_t kept = 0;
    CallbackSink sink([&](const core::PointRecord&) { ++kept; });
    const auto stats =
        render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, env, noisy()}, sink);
    const double measured = double(stats.voids) / double(stats.pulses);
    std::printf("void fraction %.5f, predicted %.5f (n_laser %.1f, n_other %.3g)\n", measured,
                predicted, n_laser, n_other);
    EXPECT_EQ(stats.voids + kept, kPulses);
    EXPECT_NEAR(predicted, 0.3173, 0.01);
    EXPECT_NEAR(measured / predicted, 1.0, 0.01);
}

}  // namespace
}  // namespace mirage::test
