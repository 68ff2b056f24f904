// SPDX-License-Identifier: Apache-2.0
// Focal-plane arrays in the pipeline (docs/photon-counting.md §3): a flash array on a Lambertian
// plane square to the laser gives every pixel the closed form (E_t/N)·FF·(ρ/π)·(A_r/R_p²)·cos θ·η
// photo-electrons; a Geiger-mode array on it fires in 1 − e^(−N) of the pulses per pixel, at the
// pixel's range, the same on any thread count.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "mirage/physics/radiometry.hpp"
#include "mirage/sensor/array.hpp"
#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

constexpr double kRange = 100.0;

// A 16 × 8 flash array, 0.5 mrad pixels, fill factor 0.8, staring along +x at a plane 100 m
// away; one laser pulse per µs unless told.
sensor::SensorModel flash_array(sensor::BeamProfile laser, int sub_rays,
                                std::int64_t period_ns = 1000) {
    auto s = test_sensor(std::make_shared<FanPattern>(std::vector{unit(1, 0, 0)}, period_ns));
    s.beam.profile = laser;
    s.beam.divergence_rad = 8e-3;
    s.beam.sub_rays = sub_rays;
    s.beam.pulse_energy_j = 1e-6;
    s.array.columns = 16;
    s.array.rows = 8;
    s.array.pitch_m = 50e-6;
    s.array.focal_length_m = 0.1;
    s.array.fill_factor = 0.8;
    sensor::make_array(s, "test");
    return s;
}

// The closed form of pixel p: its share of the pulse, times FF·(ρ/π)·A_r·cos θ/R_p² (θ its angle
// from the plane's normal, R_p = R/cos θ) and the receiver's efficiencies, in photo-electrons.
double closed_form_pe(const sensor::SensorModel& s, std::uint32_t p, double reflectance) {
    const auto& a = s.array;
    const double tx = (double(p % a.columns) - 0.5 * (a.columns - 1)) * a.ifov_rad();
    const double ty = (double(p / a.columns) - 0.5 * (a.rows - 1)) * a.ifov_rad();
    const double cos_t = 1.0 / std::sqrt(1.0 + tx * tx + ty * ty);
    const double rp = kRange / cos_t;
    const auto& rx = s.receiver;
    const double area = std::numbers::pi * rx.aperture_diameter_m * rx.aperture_diameter_m / 4;
    const double joules = s.beam.pulse_energy_j * double(a.share[p]) * a.fill_factor * reflectance /
                          std::numbers::pi * area * cos_t / (rp * rp) * rx.eta_transmitter *
                          rx.eta_receiver;
    return joules * rx.quantum_efficiency * s.beam.wavelength_m /
           (physics::kPlanckJouleSeconds * physics::kSpeedOfLightMPerS);
}

TEST(PipelineArray, flash_pixels_take_the_closed_form) {
    const auto scene = plane_scene(100.0, plane_frame(kRange, 0.0), 0.5);
    for (const auto laser : {sensor::BeamProfile::TopHat, sensor::BeamProfile::Gaussian})
        for (const int sub_rays : {1, 19}) {
            const auto s = flash_array(laser, sub_rays);
            const auto r = render_still(scene, s, 2);  // two laser pulses
            ASSERT_EQ(r.points.size(), 2u * s.array.pixels());
            double worst = 0;
            for (const auto& pt : r.points) {
                ASSERT_EQ(pt.pixel, pt.pulse % s.array.pixels());
                const double want = closed_form_pe(s, pt.pixel, 0.5);
                worst = std::max(worst, std::abs(pt.n_laser / want - 1));
            }
            std::printf(
                "flash %s laser, %d sub-ray(s): 128 pixels, worst %.2e from the closed "
                "form, relative (centre pixel %.3f pe)\n",
                laser == sensor::BeamProfile::TopHat ? "top-hat" : "Gaussian", sub_rays, worst,
                closed_form_pe(s, 4 * 16 + 8, 0.5));
            EXPECT_LT(worst, 0.005);
        }
}

// Pixel lines of sight: column c and row r sit at tangents ((c − 7.5)·ifov, (r − 3.5)·ifov) from
// the boresight, columns to the right (−y), rows down (−z); the point lands there on the plane.
TEST(PipelineArray, pixels_look_along_their_tangents) {
    const auto scene = plane_scene(100.0, plane_frame(kRange, 0.0), 0.5);
    const auto s = flash_array(sensor::BeamProfile::TopHat, 1);
    const auto r = render_still(scene, s, 1);
    ASSERT_EQ(r.points.size(), s.array.pixels());
    for (const auto& pt : r.points) {
        const double tx = (double(pt.pixel % 16) - 7.5) * 5e-4;
        const double ty = (double(pt.pixel / 16) - 3.5) * 5e-4;
        EXPECT_NEAR(pt.x, kRange, 1e-4);
        EXPECT_NEAR(pt.y, -kRange * tx, 1e-4) << pt.pixel;
        EXPECT_NEAR(pt.z, -kRange * ty, 1e-4) << pt.pixel;
    }
}

// Two renders' events, point by point: the same pulse, pixel, range and kind; the count of
// each kind (PointRecord::event).
std::array<std::size_t, 5> same_events(const std::vector<core::PointRecord>& a,
                                       const std::vector<core::PointRecord>& b) {
    std::array<std::size_t, 5> kinds{};
    EXPECT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k) {
        EXPECT_TRUE(a[k].range_m == b[k].range_m && a[k].event == b[k].event &&
                    a[k].pixel == b[k].pixel && a[k].pulse == b[k].pulse)
            << k;
        if (a[k].event < kinds.size()) kinds[a[k].event]++;
        if (::testing::Test::HasFailure()) break;
    }
    return kinds;
}

sensor::SensorModel geiger_array(double energy_j) {
    auto s = flash_array(sensor::BeamProfile::TopHat, 1);
    s.beam.pulse_energy_j = energy_j;
    s.beam.pulse_width_s = 1e-9;
    s.detector = sensor::DetectorKind::Geiger;
    s.geiger.bin_ns = 0.25;
    s.receiver.min_range_m = 90;
    s.receiver.max_range_m = 110;
    return s;
}

// Each pixel fires in 1 − e^(−N) of the laser pulses (N its closed-form signal; noise off: no dark
// counts, background, jitter or afterpulses), at its range within the pulse's spread.
TEST(PipelineArray, geiger_pixels_fire_as_poisson_says) {
    const auto scene = plane_scene(100.0, plane_frame(kRange, 0.0), 0.5);
    auto s = geiger_array(0.0);
    const double centre = closed_form_pe(flash_array(sensor::BeamProfile::TopHat, 1), 0, 0.5) /
                          1e-6;            // photo-electrons per joule of the laser pulse, pixel 0
    s.beam.pulse_energy_j = 1.0 / centre;  // pixel 0 expects one photo-electron
    const std::uint64_t frames = 4000;
    const auto r = render_still(scene, s, frames);
    std::vector<std::uint64_t> fired(s.array.pixels(), 0);
    double worst_range = 0;
    for (const auto& pt : r.points) {
        ASSERT_EQ(pt.event, 1);  // signal
        ASSERT_EQ(pt.return_number, 1);
        fired[pt.pixel]++;
        const double tx = (double(pt.pixel % 16) - 7.5) * 5e-4;
        const double ty = (double(pt.pixel / 16) - 3.5) * 5e-4;
        const double rp = kRange * std::sqrt(1 + tx * tx + ty * ty);
        worst_range = std::max(worst_range, std::abs(pt.range_m - rp));
    }
    double worst = 0, mean_p = 0;
    for (std::uint32_t p = 0; p < s.array.pixels(); ++p) {
        const double want = -std::expm1(-closed_form_pe(s, p, 0.5));
        const double got = double(fired[p]) / double(frames);
        worst = std::max(worst, std::abs(got - want));
        mean_p += want / s.array.pixels();
    }
    std::printf(
        "Geiger flash array: 128 pixels x %llu pulses, detection against 1 - e^-N "
        "(mean %.4f): worst pixel %.4f absolute; worst range error %.3f m\n",
        static_cast<unsigned long long>(frames), mean_p, worst, worst_range);
    EXPECT_LT(worst, 0.03);       // 4.4 sigma of a share near 0.63 over 4000 pulses
    EXPECT_LT(worst_range, 0.6);  // ±4σ of a 1 ns FWHM pulse (c·σ/2 = 64 mm) and a 37 mm bin
}

// Events do not depend on the thread count (pulse-keyed random numbers).
TEST(PipelineArray, geiger_events_are_the_same_on_any_thread_count) {
    const auto scene = plane_scene(100.0, plane_frame(kRange, 0.0), 0.5);
    auto s = geiger_array(2e-10);
    s.geiger.max_events = 3;
    s.geiger.dead_time_ns = 5;
    s.geiger.dark_count_rate_hz = 5e6;
    s.geiger.jitter_ns = 0.2;
    s.geiger.afterpulse_probability = 0.2;
    s.geiger.afterpulse_delay_ns = 20;
    std::vector<core::PointRecord> runs[2];
    for (int threads : {1, 2}) {
        render::EmbreeRenderer rr(scene);
        render::RenderOptions o;
        o.noise = true;
        o.threads = threads;
        o.chunk_pulses = 1024;
        o.duration = core::Nanos(3000 * 1000);  // 3000 laser pulses
        VectorSink sink;
        render::render({scene, rr, s, core::Trajectory::fixed({}), {}, {}, o}, sink);
        runs[threads - 1] = sink.points;
    }
    ASSERT_GT(runs[0].size(), 1000u);
    std::array<std::size_t, 5> kinds{};
    ASSERT_NO_FATAL_FAILURE(kinds = same_events(runs[0], runs[1]));
    std::printf("events over 3000 pulses x 128 pixels: %zu signal, %zu noise, %zu afterpulse\n",
                kinds[1], kinds[2], kinds[3]);
    EXPECT_GT(kinds[1], 0u);
    EXPECT_GT(kinds[2], 0u);
    EXPECT_GT(kinds[3], 0u);
}

// Crosstalk: a detection fires each in-array neighbour with the configured probability (0.05).
// Dark counts only (0.02 per pixel and gate), one event per gate: a neighbour is blocked only by
// its own earlier event (about 1 % of the time), so crosstalk events over the neighbours of all
// detections come within 5 % of the probability. Without crosstalk there is none.
TEST(PipelineArray, crosstalk_fires_neighbours_as_configured) {
    const auto scene = plane_scene(100.0, plane_frame(kRange, 0.0), 0.5);
    for (const double px : {0.05, 0.0}) {
        auto s = geiger_array(1e-18);
        s.geiger.dark_count_rate_hz = 0.02 / (20 * 2 / 0.299792458 * 1e-9);
        s.geiger.dead_time_ns = 1000;
        s.geiger.crosstalk_probability = px;
        const std::uint64_t frames = 10000;
        const auto r = render_still(scene, s, frames, true);
        double neighbours = 0;
        std::size_t crosstalk = 0;
        // Every detection fires its neighbours, crosstalk too (a crosstalk's source is fired
        // already: one neighbour fewer).
        for (const auto& pt : r.points) {
            const std::uint32_t c = pt.pixel % 16, row = pt.pixel / 16;
            neighbours += (c > 0) + (c < 15) + (row > 0) + (row < 7);
            if (pt.event == 4) {
                crosstalk++;
                neighbours -= 1;
            }
        }
        std::printf(
            "crosstalk %.2f: %zu events over %zu own detections, %.0f neighbours: %.5f per "
            "neighbour (%+.2f %%)\n",
            px, crosstalk, r.points.size() - crosstalk, neighbours, double(crosstalk) / neighbours,
            px > 0 ? 100 * (double(crosstalk) / neighbours / px - 1) : 0.0);
        if (px == 0.0)
            EXPECT_EQ(crosstalk, 0u);
        else
            EXPECT_NEAR(double(crosstalk) / neighbours / px, 1.0, 0.05);
    }
}

// A pixel that reports its first event only takes its own path (a dense event per pixel, the
// first event straight from its arrivals, crosstalk in closed form); with a dead time longer than
// the gate, one that may report three cannot detect twice either, and goes the general way (the
// rate built, the draw, crosstalk event by event in time order): the same points. Signal near one
// photo-electron a pixel, dark counts, jitter and crosstalk on.
TEST(PipelineArray, a_first_event_pixel_matches_the_general_draw) {
    const auto scene = plane_scene(100.0, plane_frame(kRange, 0.0), 0.5);
    const double centre =
        closed_form_pe(flash_array(sensor::BeamProfile::TopHat, 1), 0, 0.5) / 1e-6;
    auto s = geiger_array(1.0 / centre);
    s.geiger.dark_count_rate_hz = 0.3 / (20 * 2 / 0.299792458 * 1e-9);
    s.geiger.dead_time_ns = 1000;  // the gate: 133 ns
    s.geiger.jitter_ns = 0.24;
    s.geiger.crosstalk_probability = 0.05;
    std::vector<core::PointRecord> runs[2];
    for (const std::uint32_t max : {1u, 3u}) {
        s.geiger.max_events = max;
        runs[max / 2] = render_still(scene, s, 2000, true).points;
    }
    ASSERT_GT(runs[0].size(), 100000u);
    std::array<std::size_t, 5> kinds{};
    ASSERT_NO_FATAL_FAILURE(kinds = same_events(runs[0], runs[1]));
    std::printf("2000 frames x 128 pixels: %zu signal, %zu noise, %zu crosstalk events, alike\n",
                kinds[1], kinds[2], kinds[4]);
    EXPECT_GT(kinds[1], 10000u);
    EXPECT_GT(kinds[2], 10000u);
    EXPECT_GT(kinds[4], 1000u);
}

// A free-running array in the dark (docs/photon-counting.md §2.1): dark counts only, r = 1 per
// 1.5 µs per pixel, a dead time of 1.5 µs, laser pulses 2 µs apart and the gate from 1 to 280 m
// (W = 1.861 µs of each 2 µs reported). In the steady state a pixel counts r/(1 + rτ)
// (non-paralyzable) or r·e^(−rτ) (paralyzable) at any moment, so a window reports W times that:
// within 1 % over 128 pixels × 1990 windows (the first 10 skipped). Rendered on 2 threads in
// chunks of 3 frames, so the dead time crosses chunks and threads; the same on 1 thread.
TEST(PipelineArray, a_free_running_array_carries_its_dead_time_across_pulses) {
    const auto scene = plane_scene(100.0, plane_frame(kRange, 0.0), 0.5);
    const std::uint64_t frames = 2000, skip = 10;
    for (const bool paralyzable : {false, true}) {
        auto s = flash_array(sensor::BeamProfile::TopHat, 1, 2000);
        s.beam.pulse_energy_j = 1e-18;
        s.beam.pulse_width_s = 1e-9;
        s.detector = sensor::DetectorKind::Geiger;
        s.receiver.min_range_m = 1;
        s.receiver.max_range_m = 280;
        s.geiger.dark_count_rate_hz = 1e9 / 1500;
        s.geiger.dead_time_ns = 1500;
        s.geiger.paralyzable = paralyzable;
        s.geiger.max_events = 4;
        s.geiger.free_running = true;
        std::vector<core::PointRecord> runs[2];
        for (const int threads : {2, 1}) {
            render::EmbreeRenderer rr(scene);
            render::RenderOptions o;
            o.noise = true;
            o.threads = threads;
            o.chunk_pulses = 3 * 128;
            o.duration = core::Nanos(static_cast<std::int64_t>(frames) * 2000);
            VectorSink sink;
            render::render({scene, rr, s, core::Trajectory::fixed({}), {}, {}, o}, sink);
            runs[threads - 1] = sink.points;
        }
        ASSERT_EQ(runs[0].size(), runs[1].size());
        for (std::size_t k = 0; k < runs[0].size(); ++k)
            ASSERT_TRUE(runs[0][k].range_m == runs[1][k].range_m &&
                        runs[0][k].pixel == runs[1][k].pixel)
                << k;
        std::uint64_t counted = 0;
        for (const auto& pt : runs[1]) counted += pt.pulse / 128 >= skip;
        const double r = 1.0 / 1500, tau = 1500;
        const double window = 2 * (280 - 1) / physics::kSpeedOfLightMPerS * 1e9;
        const double want = window * (paralyzable ? r * std::exp(-r * tau) : r / (1 + r * tau));
        const double got = double(counted) / double(128 * (frames - skip));
        std::printf(
            "free-running %s array, dead time 1.5 us, pulses 2 us apart: %.4f events per window, "
            "steady-state law %.4f (%+.2f %%)\n",
            paralyzable ? "paralyzable" : "non-paralyzable", got, want, 100 * (got / want - 1));
        EXPECT_NEAR(got / want, 1.0, 0.01);
    }
}

}  // namespace
}  // namespace mirage::test
