// SPDX-License-Identifier: Apache-2.0
// Windowed rendering: a few pulses at a time on the calling thread, for live emulation.
#include "mirage/render/pipeline.hpp"
#include "ray_batch.hpp"
#include "shading.hpp"

namespace mirage::render {

// The environment and options are copied: PulseShader keeps references, and callers may pass
// temporaries. Scene, renderer and sensor must outlive the WindowRenderer.
struct WindowRenderer::Impl {
    Impl(const scene::Scene& scene, const Renderer& r, const sensor::SensorModel& s,
         const core::Mount& m, const physics::Environment& e, const RenderOptions& o)
        : renderer(r), sensor(s), mount(m), env(e), opt(o), shader(scene, s, env, opt) {}
    const Renderer& renderer;
    const sensor::SensorModel& sensor;
    core::Mount mount;
    physics::Environment env;
    RenderOptions opt;
    PulseShader shader;  // after env and opt, which it refers to
    RayBatch g;
    std::vector<Hit> hits;
    ShadeScratch scratch;
    ShadedPoints result;
};

WindowRenderer::WindowRenderer(const scene::Scene& scene, const Renderer& renderer,
                               const sensor::SensorModel& sensor, const core::Mount& mount,
                               const physics::Environment& env, const RenderOptions& opt)
    : impl_(std::make_unique<Impl>(scene, renderer, sensor, mount, env, opt)) {}

WindowRenderer::~WindowRenderer() = default;

void WindowRenderer::render(const core::Trajectory& trajectory, std::uint64_t first, std::size_t n,
                            std::vector<core::PointRecord>& out, RenderStats& stats) {
    Impl& m = *impl_;
    const RayBatchBuilder builder(m.sensor, trajectory, m.mount, m.opt.start);
    m.result.points.swap(out);
    m.result.stats = {};
    builder.for_each_batch(first, n, m.g, [&](const RayBatch& g) {
        m.hits.resize(g.rays.size());
        m.renderer.intersect(g.rays, m.hits);
        m.shader.shade(g, m.hits, builder.subrays(), m.scratch, m.result);
    });
    m.result.points.swap(out);
    stats.add(m.result.stats);
}

}  // namespace mirage::render
