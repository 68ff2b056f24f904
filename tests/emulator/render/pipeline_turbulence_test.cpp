// SPDX-License-Identifier: Apache-2.0
// Turbulence in the pipeline (docs/time-resolved.md §6): over 1e5 pulses on a tilted plane the
// range varies as the wander moves the beam across the slope, by the closed form, both
// detectors, the same on any thread count; nothing moves without noise or turbulence. The
// short-term spread widens a footprint's delays by the closed form (sampled and adaptive), and
// the image's wander with the beam's moves a narrow pixel off a point-like spot as often as the
// Rayleigh law of their summed variances says.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mirage/render/pulse_probe.hpp"
#include "mirage/sensor/presets.hpp"
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

// A plane square to the beam at 200 m, C_n² = 1e-13, noise on, and a pixel of 24 µrad
// field-of-view half-angle: `pulses` pulses of a beam of full divergence `divergence`.
std::vector<core::PointRecord> narrow_pixel_render(int threads, int sub_rays, double divergence,
                                                   bool adaptive, std::int64_t pulses) {
    const auto scene = plane_scene(2000.0, plane_frame(200.0, 0.0));
    render::EmbreeRenderer r(scene);
    auto sensor = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, 100));
    sensor.beam.sub_rays = sub_rays;
    sensor.beam.divergence_rad = divergence;
    sensor.beam.adaptive_footprint = adaptive;
    sensor.receiver.detector_area_m2 = sensor::detector_area_for_ifov(
        2 * 24e-6, sensor.receiver.aperture_diameter_m, sensor.receiver.f_number);
    physics::Environment env;
    env.turbulence.cn2 = 1e-13;
    render::RenderOptions o;
    o.threads = threads;
    o.duration = core::Nanos(pulses * 100);
    VectorSink sink;
    render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, env, o}, sink);
    return sink.points;
}

// A plane at 2 km tilted by S = 45°, a beam of 1/e² half-angle θ_b = 100 µrad, C_n² = 5e-13,
// noise off (the spread is the short-term spot's, not a fluctuation): the delays' variance is the
// tilted-plane law cut·(tan S/c)²·(R²·tan²θ_b + ΔW²), ΔW² = 1.2525·C_n²·R³·w0^(−1/3) (here
// 0.54 of the spot's own R²·tan²θ_b). Sampled 37 sub-rays: the variance grows by that factor;
// adaptive: the closed form follows the law.
TEST(PipelineTurbulence, beam_spread_widens_the_footprint_by_the_short_term_law) {
    const double d = 2000, tilt = kPi / 4, theta_b = 100e-6, cn2 = 5e-13, w0 = 0.0125;
    const double spot2 = d * d * std::tan(theta_b) * std::tan(theta_b);
    const double spread2 = 1.2525 * cn2 * d * d * d / std::cbrt(w0);
    const auto scene = plane_scene(1000.0, plane_frame(d, tilt));
    render::EmbreeRenderer r(scene);
    const auto variance = [&](int sub_rays, bool adaptive, double c) {
        auto sensor = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, 1000));
        sensor.beam.sub_rays = sub_rays;
        sensor.beam.divergence_rad = 2 * theta_b;
        sensor.beam.adaptive_footprint = adaptive;
        sensor.beam.pulse_width_s = 4e-9;
        sensor.detector = sensor::DetectorKind::Linear;
        physics::Environment env;
        env.turbulence.cn2 = c;
        render::RenderOptions o;
        o.noise = false;
        o.duration = core::Nanos(1000);
        const render::Setup setup{scene, r, sensor, core::Trajectory::fixed({}), {}, env, o};
        return delay_variance_ns2(render::pulse_arrivals(setup, 0));
    };
    const double grow = variance(37, false, cn2) / variance(37, false, 0);
    const double cut = (1 - 3 * std::exp(-2.0)) / (1 - std::exp(-2.0));
    const double c_ns = physics::kSpeedOfLightMPerS * 1e-9;
    const double law = cut * (spot2 + spread2) / (c_ns * c_ns);  // tan S = 1
    const double adaptive = variance(19, true, cn2);
    std::printf(
        "beam spread at 2 km: sampled 37 delay variance x %.4f, law x %.4f (%+.3f %%); "
        "adaptive %.5f ns2 against the law %.5f ns2 (%+.3f %%)\n",
        grow, 1 + spread2 / spot2, 100 * (grow / (1 + spread2 / spot2) - 1), adaptive, law,
        100 * (adaptive / law - 1));
    EXPECT_NEAR(grow / (1 + spread2 / spot2), 1.0, 0.005);
    EXPECT_NEAR(adaptive / law, 1.0, 0.02);
}

// A point-like spot (θ_b = 0.5 µrad, one sub-ray) at 200 m, noise on, C_n² = 1e-13, and a pixel
// of field-of-view half-angle ρ = 24 µrad: the beam wanders by α (σ_α² = 1.21·C_n²·L·w0^(−1/3)
// per axis) and the image by β (σ_β² = 1.09·C_n²·L·D^(−1/3)), drawn independently, and the pixel
// sees the spot while |α − β| < ρ: P = 1 − exp(−ρ²/(2(σ_α² + σ_β²))) (Rayleigh). From the share of
// 1e5 pulses that return, the image wander's variance (the beam wander's, tested above, taken
// off) within 3 %; the same points on 1 and 2 threads.
TEST(PipelineTurbulence, image_wander_moves_a_narrow_pixel_off_the_spot) {
    const double l = 200, cn2 = 1e-13, rho = 24e-6;
    const std::int64_t pulses = 100'000;
    const auto run = [&](int threads) {
        return narrow_pixel_render(threads, 1, 1e-6, false, pulses);
    };
    const auto pts = run(2);
    const double d = 0.025, w0 = d / 2;
    const double beam = 1.21 * cn2 * l / std::cbrt(w0), image = 1.09125 * cn2 * l / std::cbrt(d);
    const double p = double(pts.size()) / double(pulses);
    const double total = rho * rho / (-2 * std::log(1 - p)), got = total - beam;
    std::printf(
        "image wander at 200 m: %.4f of pulses seen by a 24 urad pixel (law %.4f); image "
        "variance %.4e rad2 against %.4e (%+.2f %%), the beam's %.4e\n",
        p, 1 - std::exp(-rho * rho / (2 * (beam + image))), got, image, 100 * (got / image - 1),
        beam);
    EXPECT_NEAR(got / image, 1.0, 0.03);
    const auto one = run(1);
    ASSERT_EQ(one.size(), pts.size());
    for (std::size_t k = 0; k < pts.size(); ++k)
        ASSERT_TRUE(one[k].range_m == pts[k].range_m && one[k].pulse == pts[k].pulse)
            << "1 and 2 threads differ at " << k;
}

// A spot of 20 µrad full divergence, 19 sub-rays, under the same pixel: the wandering field of
// view cuts part of some footprints. Adaptive footprints take the closed form only where the
// whole footprint stays inside it, so over 2e4 pulses they return from the same pulses as the
// sampled 19 (the pulses it cuts are sampled in both), and from fewer than a spot-wide pixel.
TEST(PipelineTurbulence, image_wander_cuts_an_adaptive_footprint_as_a_sampled_one) {
    const std::int64_t pulses = 20'000;
    const auto sampled = narrow_pixel_render(2, 19, 20e-6, false, pulses);
    const auto adaptive = narrow_pixel_render(2, 19, 20e-6, true, pulses);
    std::printf(
        "20 urad spot, 24 urad pixel, 2e4 pulses: sampled 19 returns from %zu, adaptive "
        "from %zu\n",
        sampled.size(), adaptive.size());
    ASSERT_EQ(adaptive.size(), sampled.size());
    for (std::size_t k = 0; k < sampled.size(); ++k)
        ASSERT_EQ(adaptive[k].pulse, sampled[k].pulse) << k;
    EXPECT_LT(sampled.size(), std::size_t(pulses) * 99 / 100);
}

}  // namespace
}  // namespace mirage::test
