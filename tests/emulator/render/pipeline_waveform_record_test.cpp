// SPDX-License-Identifier: Apache-2.0
// The waveforms a render records (docs/time-resolved.md §13): each return's window holds its
// echo where the point says, the floor elsewhere, the same on any thread count; only the
// linear detector records.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mirage/core/error.hpp"
#include "pipeline_fixtures.hpp"

namespace mirage::test {
namespace {

constexpr std::uint32_t kWindow = 64;

// Keeps points and samples, with each point's `wave` made an index into all samples kept.
class RecordingSink : public render::PointSink {
  public:
    void write(std::span<const core::PointRecord> p) override { write_recorded(p, {}); }
    void write_recorded(std::span<const core::PointRecord> p,
                        std::span<const std::uint32_t> s) override {
        const auto base = static_cast<std::uint32_t>(samples.size());
        samples.insert(samples.end(), s.begin(), s.end());
        for (core::PointRecord q : p) {
            if (q.wave != core::PointRecord::kNoWave) q.wave += base;
            points.push_back(q);
        }
    }
    std::vector<core::PointRecord> points;
    std::vector<std::uint32_t> samples;
};

sensor::SensorModel sensor_of(sensor::DetectorKind kind) {
    std::vector<Eigen::Vector3f> dirs;
    for (int k = 0; k < 100; ++k) dirs.push_back(unit(1, 0.002 * (k % 11), 0.003 * (k % 7)));
    auto s = test_sensor(std::make_shared<FanPattern>(std::move(dirs), 1000));
    s.beam.pulse_width_s = 4e-9;
    s.beam.sub_rays = 7;
    s.beam.pulse_energy_j = 1e-8;  // echoes of ~500 counts: inside the 12-bit digitiser's range
    s.detector = kind;
    return s;
}

RecordingSink render_recorded(const sensor::SensorModel& sensor, int threads, bool noise = true) {
    const auto scene = plane_scene(2000.0, plane_frame(80.0, 0.3));
    render::EmbreeRenderer r(scene);
    render::RenderOptions o;
    o.threads = threads;
    o.noise = noise;
    o.duration = core::Nanos(2000 * 1000);  // 2000 pulses
    o.waveform_samples = kWindow;
    RecordingSink sink;
    render::render({scene, r, sensor, core::Trajectory::fixed({}), {}, {}, o}, sink);
    return sink;
}

TEST(PipelineWaveformRecord, each_window_peaks_where_its_return_lies) {
    const auto sensor = sensor_of(sensor::DetectorKind::Linear);
    const RecordingSink got = render_recorded(sensor, 2);
    ASSERT_GT(got.points.size(), 1900u);
    const double period_ps = 1e3 / sensor.linear.sample_rate_gsps;
    double worst = 0, floor_sum = 0, floor_n = 0;
    for (const core::PointRecord& p : got.points) {
        ASSERT_NE(p.wave, core::PointRecord::kNoWave);
        ASSERT_LE(std::size_t{p.wave} + kWindow, got.samples.size());
        const std::uint32_t* s = got.samples.data() + p.wave;
        const auto peak = static_cast<double>(std::max_element(s, s + kWindow) - s);
        worst = std::max(worst, std::abs(peak - p.wave_location_ps / period_ps));
        for (std::uint32_t j = 40; j < kWindow; ++j) floor_sum += s[j], floor_n += 1;
        ASSERT_GT(p.amplitude, 0.0f);
        ASSERT_TRUE(p.echo_width_ns >= 0.0f && std::isfinite(p.echo_width_ns));
        ASSERT_TRUE(p.deviation >= 0.0f && std::isfinite(p.deviation));
    }
    const double floor = floor_sum / floor_n;
    std::printf("worst peak-to-return distance %.2f samples; floor %.2f counts (offset %.0f)\n",
                worst, floor, sensor.linear.offset_counts);
    EXPECT_LE(worst, 1.0);
    EXPECT_NEAR(floor, sensor.linear.offset_counts, 1.0);  // no sun, no dark current here
}

// Without noise a facet's echo is the pulse itself: the fit's width is σ_p (a 4 ns FWHM), its
// amplitude the window's peak above the offset, and the samples follow the fit to a fraction of
// the rounding to whole counts.
TEST(PipelineWaveformRecord, noise_free_echo_fields_are_the_pulse_s) {
    const auto sensor = sensor_of(sensor::DetectorKind::Linear);
    const RecordingSink got = render_recorded(sensor, 2, false);
    ASSERT_GT(got.points.size(), 1900u);
    const double sigma_p = 4.0 / (2 * std::sqrt(2 * std::log(2.0)));
    double worst_width = 0, worst_amp = 0, worst_dev = 0;
    for (const core::PointRecord& p : got.points) {
        const std::uint32_t* s = got.samples.data() + p.wave;
        const double peak = *std::max_element(s, s + kWindow) - sensor.linear.offset_counts;
        worst_width = std::max(worst_width, std::abs(p.echo_width_ns / sigma_p - 1));
        worst_amp = std::max(worst_amp, std::abs(p.amplitude / peak - 1));
        worst_dev = std::max(worst_dev, double(p.deviation));
    }
    std::printf(
        "worst: width %.2f %% from sigma_p, amplitude %.2f %% above the peak sample, "
        "deviation %.2f counts\n",
        100 * worst_width, 100 * worst_amp, worst_dev);
    EXPECT_LT(worst_width, 0.05);  // the tilt (0.3 rad, 3 mrad beam) widens it by < 1 %
    EXPECT_LT(worst_amp, 0.20);    // the fitted peak lies up to half a sample from a sample
    EXPECT_LT(worst_dev, 0.5);
}

TEST(PipelineWaveformRecord, recorded_samples_are_identical_on_any_thread_count) {
    const auto sensor = sensor_of(sensor::DetectorKind::Linear);
    const RecordingSink one = render_recorded(sensor, 1), two = render_recorded(sensor, 2);
    EXPECT_EQ(one.samples, two.samples);
    ASSERT_EQ(one.points.size(), two.points.size());
    for (std::size_t k = 0; k < one.points.size(); ++k)
        ASSERT_EQ(one.points[k].wave_location_ps, two.points[k].wave_location_ps);
}

TEST(PipelineWaveformRecord, only_the_linear_detector_records) {
    EXPECT_THROW(render_recorded(sensor_of(sensor::DetectorKind::Discrete), 1), ConfigError);
}

}  // namespace
}  // namespace mirage::test
