// SPDX-License-Identifier: Apache-2.0
// render() ends the chain of stages it starts: PointSink::finish() exactly once, after the last
// write, also when stopped early, and never after a failure; the LAS sink's finish closes its file.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>

#include "mirage/las/las_reader.hpp"
#include "mirage/las/las_sink.hpp"
#include "mirage/las/las_writer.hpp"
#include "mirage/output/packetizer_sink.hpp"
#include "pipeline_fixtures.hpp"
#include "test_paths.hpp"

namespace mirage::test {
namespace {

// Logs every call: w(rite), e(ncoded write), d(one pulses), f(inish). Optionally encodes on the
// workers, sets `stop` after its first write, or throws on its second.
class CountingSink : public render::PointSink {
  public:
    void write(std::span<const core::PointRecord>) override { on_write('w'); }
    void pulses_done(std::uint64_t next) override {
        calls += 'd';
        last_done = next;
    }
    void finish() override { calls += 'f'; }
    std::unique_ptr<render::EncodedPoints> new_encoded() const override {
        return encodes ? std::make_unique<Nothing>() : nullptr;
    }
    void write_encoded(render::EncodedPoints&) override { on_write('e'); }

    bool encodes = false, throw_on_second = false;
    std::atomic<bool>* stop_after_first = nullptr;
    std::string calls;
    std::uint64_t last_done = 0;

  private:
    struct Nothing : render::EncodedPoints {
        void clear() override {}
    };
    void on_write(char c) {
        if (throw_on_second && calls.find(c) != std::string::npos)
            throw std::runtime_error("disk full");
        calls += c;
        if (stop_after_first) stop_after_first->store(true);
    }
};

struct Fixture {
    scene::Scene scene = plane_scene(400.0, Eigen::Affine3d::Identity(), 0.3);
    render::EmbreeRenderer renderer{scene};
    sensor::SensorModel sensor = sensor::preset("vlp16");
    core::Trajectory trajectory =
        core::Trajectory::fixed({{0, 0, 1.8}, Eigen::Quaterniond::Identity()});
    render::RenderOptions options;
    Fixture() {
        options.threads = 2;
        options.chunk_pulses = 512;
        options.duration = std::chrono::milliseconds(50);
    }
    render::Setup setup() const { return {scene, renderer, sensor, trajectory, {}, {}, options}; }
    std::uint64_t total() const { return sensor.scan->pulse_count(options.duration); }
};

std::size_t count(const std::string& s, char c) {
    return static_cast<std::size_t>(std::count(s.begin(), s.end(), c));
}

TEST(PipelineSink, finish_is_called_once_after_the_last_write) {
    const Fixture fx;
    for (bool encodes : {false, true}) {
        CountingSink sink;
        sink.encodes = encodes;
        render::render(fx.setup(), sink);
        const char write = encodes ? 'e' : 'w';
        const std::size_t chunks = (fx.total() + 511) / 512;
        EXPECT_EQ(count(sink.calls, write), chunks) << encodes;
        EXPECT_EQ(count(sink.calls, 'f'), 1u) << encodes;
        EXPECT_EQ(sink.calls.back(), 'f') << encodes;
        EXPECT_EQ(sink.last_done, fx.total()) << encodes;
    }
}

TEST(PipelineSink, a_render_stopped_early_still_finishes_its_sink_once) {
    const Fixture fx;
    std::atomic<bool> stop{false};
    CountingSink sink;
    sink.stop_after_first = &stop;
    const auto stats = render::render(fx.setup(), sink, {}, &stop);
    EXPECT_LT(stats.pulses, fx.total());
    EXPECT_LT(sink.last_done, fx.total());
    EXPECT_GE(count(sink.calls, 'w'), 1u);
    EXPECT_EQ(count(sink.calls, 'f'), 1u);
    EXPECT_EQ(sink.calls.back(), 'f');
}

TEST(PipelineSink, a_failing_sink_is_not_finished) {
    const Fixture fx;
    CountingSink sink;
    sink.throw_on_second = true;
    EXPECT_THROW(render::render(fx.setup(), sink), std::runtime_error);
    EXPECT_EQ(sink.calls, "wd");
}

// Points written by the writing thread sit in the writer's buffer until it is closed: the file
// holds all of them as soon as render() returns, before the writer is destroyed.
TEST(PipelineSink, las_sink_finish_closes_the_file) {
    const Fixture fx;
    TempDir tmp;
    const auto path = tmp.file("finish.las");
    las::LasWriter writer(path, fx.scene.georef);
    std::vector<core::PointRecord> copy;
    las::LasSink sink(writer, &copy);
    const auto stats = render::render(fx.setup(), sink);
    ASSERT_GT(stats.points, 1000u);
    const las::LasFile file = las::LasFile::read(path);
    EXPECT_EQ(file.header().point_count, stats.points);
    EXPECT_EQ(file.records_in_file(), stats.points);
    EXPECT_TRUE(file.validate().empty());
}

// The packetizer behind emulate's sink is finished by render(), once, after its last pulses.
TEST(PipelineSink, packetizer_sink_finish_finishes_the_packetizer) {
    const Fixture fx;
    struct Log : wire::Packetizer {
        std::string calls;
        std::uint64_t next = 0;
        void add(std::span<const core::PointRecord>) override { calls += 'a'; }
        void advance_to(std::uint64_t n) override {
            calls += 'v';
            next = n;
        }
        void emit_side_packets_until(core::GpsTime) override { calls += 's'; }
        void finish() override { calls += 'f'; }
    } packetizer;
    output::PacketizerSink sink(packetizer);
    render::render(fx.setup(), sink);
    EXPECT_EQ(count(packetizer.calls, 'f'), 1u);
    EXPECT_EQ(packetizer.calls.back(), 'f');
    EXPECT_EQ(packetizer.next, fx.total());
}

}  // namespace
}  // namespace mirage::test
