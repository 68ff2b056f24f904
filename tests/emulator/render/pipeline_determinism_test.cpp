// SPDX-License-Identifier: Apache-2.0
// Counter-based randomness keyed by (seed, pulse, stream): the same seed gives a byte-identical
// LAS file on 1 and 2 threads and for any chunk size; another seed gives another file.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <numbers>

#include "mirage/las/las_sink.hpp"
#include "mirage/las/las_writer.hpp"
#include "pipeline_fixtures.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

std::string render_file(const TempDir& tmp, const std::string& name, int threads, std::size_t chunk,
                        std::uint64_t seed, std::size_t window_chunks = 0,
                        bool encode_on_workers = false) {
    scene::Scene s = plane_scene(400.0, Eigen::Affine3d::Identity(), 0.3);
    Eigen::Affine3d wall = Eigen::Affine3d::Identity();
    wall.translate(Eigen::Vector3d(20, 0, 0));
    wall.rotate(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY()));
    s.add_mesh(quad(30.0, wall));
    render::EmbreeRenderer r(s);
    auto sensor = sensor::preset("vlp16");
    sensor.beam.sub_rays = 7;
    sensor.receiver.noise_irradiance_sigma = 5.0;
    sensor.noise.range_sigma_m = 0.03;
    sensor.noise.jitter_sigma_rad = 2e-4;
    physics::Environment env;
    env.sun.elevation_rad = 0.5;
    env.sun.irradiance_w_m2_um = 700;
    render::RenderOptions opt;
    opt.seed = seed;
    opt.threads = threads;
    opt.chunk_pulses = chunk;
    opt.window_chunks = window_chunks;
    opt.duration = std::chrono::milliseconds(200);
    std::vector<core::StampedPose> samples{
        {core::GpsTime{}, {{0, 0, 1.8}, core::quaternion_from_rpy(0, 0, 0)}},
        {core::GpsTime{} + std::chrono::seconds(1),
         {{10, 2, 1.8}, core::quaternion_from_rpy(0.01, 0, 1.0)}}};
    const auto path = tmp.file(name);
    las::LasWriter w(path, s.georef);
    // A copy of the points makes the sink encode on the writing thread.
    std::vector<core::PointRecord> copy;
    las::LasSink sink(w, encode_on_workers ? nullptr : &copy);
    render::render({s, r, sensor, core::Trajectory(samples), {}, env, opt}, sink);
    std::ifstream f(path, std::ios::binary);  // closed by the sink's finish()
    return {std::istreambuf_iterator<char>(f), {}};
}

TEST(PipelineDeterminism, same_seed_gives_byte_identical_las_on_one_and_two_threads) {
    TempDir tmp;
    const std::string one = render_file(tmp, "t1.las", 1, 8192, 5);
    const std::string two = render_file(tmp, "t2.las", 2, 8192, 5);
    const std::string two_small = render_file(tmp, "t2s.las", 2, 512, 5);
    const std::string other = render_file(tmp, "o.las", 2, 8192, 6);
    ASSERT_GT(one.size(), 375u + 30u * 10000u);
    EXPECT_TRUE(one == two) << "1 vs 2 threads differ";
    EXPECT_TRUE(one == two_small) << "chunk size changes the output";
    EXPECT_FALSE(one == other) << "the seed has no effect";
    // Records encoded on the workers (the LAS sink's default) make the same file.
    const std::string encoded = render_file(tmp, "t2e.las", 2, 512, 5, 0, true);
    EXPECT_TRUE(one == encoded) << "encoding on the workers changes the output";
}

// How far the workers may run ahead of the writer (emulate raises it for real-time output)
// changes only memory and timing, never the points.
TEST(PipelineDeterminism, render_window_does_not_change_the_output) {
    TempDir tmp;
    const std::string base = render_file(tmp, "w0.las", 2, 512, 5);
    ASSERT_GT(base.size(), 375u + 30u * 10000u);
    EXPECT_TRUE(base == render_file(tmp, "w1.las", 2, 512, 5, 1)) << "one chunk in flight";
    EXPECT_TRUE(base == render_file(tmp, "w64.las", 2, 512, 5, 64)) << "64 chunks in flight";
}

// chunks_for_lead: the fewest chunks covering the lead's pulses, at least one.
TEST(PipelineDeterminism, chunks_for_lead_covers_the_lead) {
    const auto sensor = sensor::preset("vlp16");
    const std::size_t chunk = render::chunk_pulses(sensor, 8192);
    const core::Nanos lead{300'000'000};
    const std::uint64_t pulses = sensor.scan->pulse_count(lead);
    ASSERT_GT(pulses, 8192u);
    const std::size_t n = render::chunks_for_lead(sensor, chunk, lead);
    EXPECT_GE(n * chunk, pulses);
    EXPECT_LT((n - 1) * chunk, pulses);
    EXPECT_EQ(render::chunks_for_lead(sensor, chunk, core::Nanos{0}), 1u);
}

}  // namespace
}  // namespace mirage::test

namespace mirage::test {
namespace {

// Packet encoders need to know which pulses are behind them even when a chunk has no returns
// (sky): pulses_done() reports a strictly increasing pulse count that ends at the total.
TEST(PipelineProgress, pulses_done_increases_to_the_total_and_covers_every_point) {
    scene::Scene s = plane_scene(400.0, Eigen::Affine3d::Identity(), 0.3);
    render::EmbreeRenderer r(s);
    auto sensor = sensor::preset("vlp16");
    render::RenderOptions opt;
    opt.threads = 2;
    opt.chunk_pulses = 512;
    opt.duration = std::chrono::milliseconds(50);
    std::vector<core::StampedPose> samples{
        {core::GpsTime{}, {{0, 0, 1.8}, core::quaternion_from_rpy(0, 0, 0)}}};
    struct Sink : render::PointSink {
        std::vector<std::uint64_t> done;
        std::uint64_t max_pulse_seen = 0, violations = 0, points = 0;
        void write(std::span<const core::PointRecord> p) override {
            for (const auto& q : p) {
                const std::uint64_t before = done.empty() ? 0 : done.back();
                if (q.pulse < before) ++violations;  // a point of a pulse already reported done
                max_pulse_seen = std::max(max_pulse_seen, q.pulse);
                ++points;
            }
        }
        void pulses_done(std::uint64_t next) override { done.push_back(next); }
    } sink;
    const auto stats = render::render(
        {s, r, sensor, core::Trajectory(samples), {}, physics::Environment{}, opt}, sink);
    const std::uint64_t total = sensor.scan->pulse_count(opt.duration);
    ASSERT_FALSE(sink.done.empty());
    EXPECT_EQ(sink.done.back(), total);
    EXPECT_EQ(stats.pulses, total);
    for (std::size_t i = 1; i < sink.done.size(); ++i) EXPECT_GT(sink.done[i], sink.done[i - 1]);
    EXPECT_EQ(sink.violations, 0u);
    EXPECT_GT(sink.points, 0u);
    EXPECT_LT(sink.max_pulse_seen, total);
}

}  // namespace
}  // namespace mirage::test

namespace mirage::test {
namespace {

// Live emulation renders a packet's worth of pulses at a time: the points must be those of one
// render() call over the same pulses (same per-pulse randomness). Poses between the exact ones
// every 16 pulses are blended from the two bracketing ones, and a window's last segment ends at
// its last pulse, so coordinates may differ in the last bits (< 1 µm), never more.
TEST(WindowRenderer, windows_of_any_size_give_render_s_points) {
    scene::Scene s = plane_scene(400.0, Eigen::Affine3d::Identity(), 0.3);
    render::EmbreeRenderer r(s);
    auto sensor = sensor::preset("vlp16");
    sensor.beam.sub_rays = 7;
    sensor.noise.range_sigma_m = 0.02;
    render::RenderOptions opt;
    opt.threads = 2;
    opt.duration = std::chrono::milliseconds(30);
    opt.seed = 11;
    const core::Trajectory traj(std::vector<core::StampedPose>{
        {core::GpsTime{}, {{0, 0, 1.8}, core::quaternion_from_rpy(0, 0, 0)}},
        {core::GpsTime{} + std::chrono::seconds(1),
         {{10, 2, 1.8}, core::quaternion_from_rpy(0.01, 0, 1.0)}}});
    struct Sink : render::PointSink {
        std::vector<core::PointRecord> all;
        void write(std::span<const core::PointRecord> p) override {
            all.insert(all.end(), p.begin(), p.end());
        }
    } sink;
    render::render({s, r, sensor, traj, {}, physics::Environment{}, opt}, sink);
    const std::uint64_t total = sensor.scan->pulse_count(opt.duration);
    ASSERT_GT(sink.all.size(), 2000u);
    for (std::size_t window : {384u, 1000u, 5000u}) {
        render::WindowRenderer wr({s, r, sensor, traj, {}, physics::Environment{}, opt});
        std::vector<core::PointRecord> pts;
        render::RenderStats st;
        for (std::uint64_t first = 0; first < total; first += window)
            wr.render(traj, first,
                      static_cast<std::size_t>(std::min<std::uint64_t>(window, total - first)), pts,
                      st);
        ASSERT_EQ(pts.size(), sink.all.size()) << window;
        EXPECT_EQ(st.pulses, total);
        std::size_t diff = 0;
        for (std::size_t i = 0; i < pts.size(); ++i)
            if (pts[i].pulse != sink.all[i].pulse || std::abs(pts[i].x - sink.all[i].x) > 1e-6 ||
                std::abs(pts[i].y - sink.all[i].y) > 1e-6 ||
                std::abs(pts[i].z - sink.all[i].z) > 1e-6 ||
                std::abs(int(pts[i].intensity) - int(sink.all[i].intensity)) > 1)
                ++diff;
        EXPECT_EQ(diff, 0u) << window;
    }
}

}  // namespace
}  // namespace mirage::test
