// SPDX-License-Identifier: Apache-2.0
// Beam wander in the pipeline (docs/time-resolved.md §6): over 1e5 pulses on a tilted plane the
// range varies as the wander moves the beam across the slope, by the closed form, both
// detectors, the same on any thread count; nothing moves without noise or turbulence.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<core::PointRecord> wander_render(sensor::DetectorKind kind, double cn2, bool noise,
                                             int threads, double tilt) {
    const auto scene = plane_scene(2000.0, plane_frame(200.0, tilt));
    render::EmbreeRenderer r(scene);
    auto sensor = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, 100));
    sensor.beam.pulse_width_s = 4e-9;
    sensor.beam.pulse_energy_j = 1e-3;  // the digitiser's own timing noise far below the wander's
    sensor.detector = kind;
    sensor.linear.bits = 32;
    physics::Environment env;
    env.turbulence.cn2 = cn2;
    render::RenderOptions o;
    o.noise = noise;
    o.threads = threads;
    o.duration = core::Nanos(100'000 * 100);
    VectorSink sink;
    render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, env, o}, sink);
    return sink.points;
}

double range_variance(const std::vector<core::PointRecord>& pts) {
    double m = 0, v = 0;
    for (const auto& p : pts) m += p.range_m;
    m /= double(pts.size());
    for (const auto& p : pts) v += (p.range_m - m) * (p.range_m - m);
    return v / double(pts.size() - 1);
}

// A plane at 200 m tilted by S = 45°: the beam moved by x across the slope ranges x·tan S further,
// so Var(R) = (⟨r_c²⟩/2)·tan²S with ⟨r_c²⟩ = 2.42·Cn²·L³·w0^(−1/3), w0 the aperture's radius,
// on top of the detector's own range noise (measured without turbulence and taken off).
TEST(PipelineTurbulence, range_on_a_slope_varies_by_the_beam_wander) {
    const double cn2 = 1e-13, l = 200, s = kPi / 4, w0 = 0.0125;
    const double want = 0.5 * 2.42 * cn2 * l * l * l / std::cbrt(w0) * std::tan(s) * std::tan(s);
    for (const auto kind : {sensor::DetectorKind::Discrete, sensor::DetectorKind::Linear}) {
        const auto pts = wander_render(kind, cn2, true, 2, s);
        ASSERT_EQ(pts.size(), 100'000u);
        const double own = range_variance(wander_render(kind, 0, true, 2, s));
        const double v = range_variance(pts) - own;
        const char* name = kind == sensor::DetectorKind::Linear ? "waveform" : "discrete";
        std::printf(
            "%s: range sd from the wander %.4f mm on a 45 deg slope, closed form %.4f mm (%+.2f %% "
            "in variance; the detector's own sd %.4f mm)\n",
            name, std::sqrt(v) * 1e3, std::sqrt(want) * 1e3, 100 * (v / want - 1),
            std::sqrt(own) * 1e3);
        EXPECT_NEAR(v / want, 1.0, 0.03) << name;
        const auto one = wander_render(kind, cn2, true, 1, s);
        ASSERT_EQ(one.size(), pts.size());
        for (std::size_t k = 0; k < pts.size(); ++k)
            ASSERT_TRUE(one[k].range_m == pts[k].range_m && one[k].x == pts[k].x &&
                        one[k].y == pts[k].y && one[k].z == pts[k].z)
                << name << ": 1 and 2 threads differ at " << k;
    }
}

// Without turbulence, or with noise off, the beam does not move: the range is the same for every
// pulse.
TEST(PipelineTurbulence, no_wander_without_turbulence_or_noise) {
    for (const auto& [cn2, noise] : {std::pair{0.0, true}, {1e-13, false}}) {
        const auto pts = wander_render(sensor::DetectorKind::Discrete, cn2, noise, 1, kPi / 4);
        ASSERT_FALSE(pts.empty());
        for (const auto& p : pts) ASSERT_EQ(p.range_m, pts.front().range_m) << cn2 << noise;
    }
}

}  // namespace
}  // namespace mirage::test
