// SPDX-License-Identifier: Apache-2.0
// Pulse-to-pulse energy variation and speckle (docs/time-resolved.md §6): over 1e5 pulses on one
// facet the returns' energies have mean 1 and relative standard deviation σ (beam.energy_sigma),
// with both detectors, noise off (the variation is the laser's); with speckle of M cells, relative
// variance 1/M on top of the detector's own noise.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <utility>

#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

using Points = std::vector<core::PointRecord>;

// One beam on a facet at 50 m, 1e5 pulses 100 ns apart, rendered by `kind` (a 32-bit digitiser
// never clips) twice, noise on or off, the second time with `change` made to the sensor.
std::pair<Points, Points> before_after(sensor::DetectorKind kind, bool noise,
                                       const std::function<void(sensor::SensorModel&)>& change) {
    const auto scene = plane_scene(200.0, plane_frame(50.0, 0.2));
    render::EmbreeRenderer r(scene);
    auto sensor = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, 100));
    sensor.beam.pulse_width_s = 4e-9;
    sensor.beam.pulse_energy_j = 1e-6;
    sensor.detector = kind;
    sensor.linear.bits = 32;
    render::RenderOptions o;
    o.noise = noise;
    o.duration = core::Nanos(100'000 * 100);
    VectorSink before, after;
    render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, {}, o}, before);
    change(sensor);
    render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, {}, o}, after);
    return {before.points, after.points};
}

// Mean and variance of the points' photo-electrons relative to `n0`.
std::pair<double, double> moments(const Points& pts, double n0) {
    double s = 0, ss = 0;
    for (const auto& p : pts) {
        s += p.n_laser / n0;
        ss += (p.n_laser / n0) * (p.n_laser / n0);
    }
    const double n = double(pts.size()), mean = s / n;
    return {mean, ss / n - mean * mean};
}

TEST(PipelineEnergy, returns_vary_with_the_pulse_energy_by_sigma) {
    const double sigma = 0.1;
    for (const auto kind : {sensor::DetectorKind::Discrete, sensor::DetectorKind::Linear}) {
        const auto [fixed, varied] =
            before_after(kind, false, [&](sensor::SensorModel& s) { s.beam.energy_sigma = sigma; });
        ASSERT_EQ(varied.size(), 100'000u);
        const auto [mean, var] = moments(varied, fixed.at(0).n_laser);
        const double sd = std::sqrt(var);
        std::printf("%s: mean %.5f, relative sd %.5f against sigma %.3f (%+.2f %%)\n",
                    detector_name(kind), mean, sd, sigma, 100 * (sd / sigma - 1));
        EXPECT_NEAR(mean, 1.0, 0.001);
        EXPECT_NEAR(sd / sigma, 1.0, 0.03);
    }
}

TEST(PipelineEnergy, speckle_adds_relative_variance_1_over_m) {
    const double m = 4;
    for (const auto kind : {sensor::DetectorKind::Discrete, sensor::DetectorKind::Linear}) {
        const auto [plain, speckled] =
            before_after(kind, true, [&](sensor::SensorModel& s) { s.receiver.speckle_cells = m; });
        ASSERT_EQ(plain.size(), 100'000u);
        const double n0 = moments(plain, 1.0).first;
        const auto [mean0, var0] = moments(plain, n0);
        const auto [mean, var] = moments(speckled, n0);
        // Independent factors: Var(g·x) = (1 + 1/M)(1 + v0) − 1 for E g = E x = 1.
        const double speckle_var = (1 + var) / (1 + var0) - 1;
        std::printf(
            "%s, M = %.0f: mean %.5f, speckle's relative variance %.5f against 1/M = %.3f (%+.2f "
            "%%; the detector's own %.5f)\n",
            detector_name(kind), m, mean, speckle_var, 1 / m, 100 * (speckle_var * m - 1), var0);
        EXPECT_NEAR(mean, mean0, 0.01);
        EXPECT_NEAR(speckle_var * m, 1.0, 0.03);
    }
}

}  // namespace
}  // namespace mirage::test
