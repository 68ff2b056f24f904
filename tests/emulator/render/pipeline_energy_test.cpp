// SPDX-License-Identifier: Apache-2.0
// Pulse-to-pulse energy variation (docs/time-resolved.md §6): over 1e5 pulses on one facet the
// returns' energies have mean 1 and relative standard deviation σ (beam.energy_sigma), with both
// detectors, noise off (the variation is the laser's).
#include <gtest/gtest.h>

#include <cmath>

#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

TEST(PipelineEnergy, returns_vary_with_the_pulse_energy_by_sigma) {
    const double sigma = 0.1;
    const auto scene = plane_scene(200.0, plane_frame(50.0, 0.2));
    render::EmbreeRenderer r(scene);
    for (const auto kind : {sensor::DetectorKind::Discrete, sensor::DetectorKind::Linear}) {
        auto sensor = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, 100));
        sensor.beam.pulse_width_s = 4e-9;
        sensor.beam.pulse_energy_j = 1e-6;
        sensor.detector = kind;
        sensor.linear.bits = 32;
        render::RenderOptions o;
        o.noise = false;
        o.duration = core::Nanos(100'000 * 100);
        VectorSink fixed, varied;
        render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, {}, o}, fixed);
        sensor.beam.energy_sigma = sigma;
        render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, {}, o}, varied);
        ASSERT_EQ(varied.points.size(), 100'000u);
        const double n0 = fixed.points.at(0).n_laser;
        double s = 0, ss = 0;
        for (const auto& p : varied.points) {
            const double x = p.n_laser / n0;
            s += x;
            ss += x * x;
        }
        const double mean = s / 1e5, sd = std::sqrt(ss / 1e5 - mean * mean);
        std::printf("%s: mean %.5f, relative sd %.5f against sigma %.3f (%+.2f %%)\n",
                    kind == sensor::DetectorKind::Linear ? "waveform" : "discrete", mean, sd, sigma,
                    100 * (sd / sigma - 1));
        EXPECT_NEAR(mean, 1.0, 0.001);
        EXPECT_NEAR(sd / sigma, 1.0, 0.03);
    }
}

}  // namespace
}  // namespace mirage::test
