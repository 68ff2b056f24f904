// SPDX-License-Identifier: Apache-2.0
// The benchmark's Embree ceiling traces exactly the pipeline's batches: the same rays, cut at the
// same boundaries, in the same order; its time is the makespan of render()'s chunk hand-out.
#include "ceiling.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <numbers>
#include <string>
#include <vector>

#include "mirage/render/embree_renderer.hpp"
#include "mirage/render/pipeline.hpp"
#include "mirage/sensor/sensor.hpp"

namespace mirage::test {
namespace {

// Forwards to a real renderer and logs the rays of every intersect call, byte for byte.
class RecordingRenderer : public render::Renderer {
  public:
    explicit RecordingRenderer(const render::Renderer& inner) : inner_(inner) {}
    void intersect(std::span<const render::Ray> rays, std::span<render::Hit> hits) const override {
        std::string bytes(rays.size() * sizeof(render::Ray), '\0');
        std::memcpy(bytes.data(), rays.data(), bytes.size());
        {
            std::lock_guard lk(mu_);
            calls_.push_back(std::move(bytes));
        }
        inner_.intersect(rays, hits);
    }
    std::vector<std::string> take() {
        std::lock_guard lk(mu_);
        return std::exchange(calls_, {});
    }

  private:
    const render::Renderer& inner_;
    mutable std::mutex mu_;
    mutable std::vector<std::string> calls_;
};

class NullSink : public render::PointSink {
  public:
    void write(std::span<const core::PointRecord>) override {}
};

scene::Scene ground_and_wall() {
    scene::Scene s;
    scene::Material m;
    m.name = "grey";
    m.reflectance = 0.3;
    s.add_material(m);
    scene::Mesh ground;
    ground.vertices = {{-300, -300, 0}, {300, -300, 0}, {300, 300, 0}, {-300, 300, 0}};
    ground.triangles = {{0, 1, 2}, {0, 2, 3}};
    ground.materials = {0, 0};
    scene::Mesh wall;
    wall.vertices = {{25, -40, 0}, {25, 40, 0}, {25, 40, 12}, {25, -40, 12}};
    wall.triangles = {{0, 1, 2}, {0, 2, 3}};
    wall.materials = {0, 0};
    s.add_mesh(ground);
    s.add_mesh(wall);
    return s;
}

struct Fixture {
    scene::Scene scene = ground_and_wall();
    render::EmbreeRenderer embree{scene};
    RecordingRenderer recorder{embree};
    sensor::SensorModel sensor = sensor::preset("vlp16");
    core::Trajectory trajectory{std::vector<core::StampedPose>{
        {core::GpsTime{}, {{0, 0, 1.8}, core::quaternion_from_rpy(0, 0, 0)}},
        {core::GpsTime{} + std::chrono::seconds(1),
         {{12, 3, 1.9}, core::quaternion_from_rpy(0.02, -0.01, 0.8)}}}};
    render::RenderOptions options;
    Fixture(int threads) {
        sensor.beam.sub_rays = 7;
        options.threads = threads;
        // 5 000 pulses round down to 4 992 (312 firing groups of 16): two whole trace batches
        // and a partial one per chunk, and a partial last chunk.
        options.chunk_pulses = 5000;
        options.duration = std::chrono::milliseconds(60);
    }
    render::Setup setup() const { return {scene, recorder, sensor, trajectory, {}, {}, options}; }
};

TEST(Ceiling, traces_the_pipelines_batches_in_its_order) {
    Fixture fx(1);
    const render::ChunkPlan plan = render::chunk_plan(fx.sensor, fx.options);
    ASSERT_EQ(plan.chunk, 4992u);
    ASSERT_GT(plan.chunks(), 3u);
    ASSERT_NE(plan.pulses % plan.chunk, 0u);
    NullSink sink;
    const auto stats = render::render(fx.setup(), sink);
    const std::vector<std::string> pipeline = fx.recorder.take();
    const hil::Ceiling ceiling = hil::trace_ceiling(fx.setup());
    const std::vector<std::string> traced = fx.recorder.take();
    // Per chunk: 2048 + 2048 + 896 pulses; the last chunk's batches are cut the same way.
    ASSERT_GE(pipeline.size(), 3 * (plan.chunks() - 1));
    EXPECT_EQ(pipeline[0].size(), 2048u * 7 * sizeof(render::Ray));
    EXPECT_EQ(pipeline[2].size(), 896u * 7 * sizeof(render::Ray));
    ASSERT_EQ(traced.size(), pipeline.size());
    for (std::size_t i = 0; i < pipeline.size(); ++i)
        EXPECT_TRUE(traced[i] == pipeline[i]) << "intersect call " << i;
    EXPECT_EQ(ceiling.rays, stats.rays);
    EXPECT_EQ(ceiling.pulses, stats.pulses);
    EXPECT_GT(ceiling.seconds, 0.0);
}

// With several threads the calls interleave, but the set of batches is the same.
TEST(Ceiling, traces_the_same_batches_on_two_threads) {
    Fixture fx(2);
    NullSink sink;
    render::render(fx.setup(), sink);
    std::vector<std::string> pipeline = fx.recorder.take();
    hil::trace_ceiling(fx.setup());
    std::vector<std::string> traced = fx.recorder.take();
    std::sort(pipeline.begin(), pipeline.end());
    std::sort(traced.begin(), traced.end());
    EXPECT_TRUE(pipeline == traced);
    EXPECT_GT(pipeline.size(), 6u);
}

TEST(Ceiling, makespan_schedules_chunks_in_order_on_the_first_free_thread) {
    EXPECT_DOUBLE_EQ(hil::makespan({5.0}, 2), 5.0);            // one chunk: one thread works
    EXPECT_DOUBLE_EQ(hil::makespan({1, 1, 1, 1}, 2), 2.0);     // balanced
    EXPECT_DOUBLE_EQ(hil::makespan({3, 3, 3}, 2), 6.0);        // the third waits for a thread
    EXPECT_DOUBLE_EQ(hil::makespan({4, 1, 1, 1, 1}, 2), 4.0);  // the short ones fill the other
    EXPECT_DOUBLE_EQ(hil::makespan({1, 1, 1, 1, 4}, 2), 6.0);  // the long one comes last
    EXPECT_DOUBLE_EQ(hil::makespan({2, 2, 2}, 1), 6.0);        // one thread: the sum
    EXPECT_DOUBLE_EQ(hil::makespan({}, 2), 0.0);
}

}  // namespace
}  // namespace mirage::test
