// SPDX-License-Identifier: Apache-2.0
// Windowed rendering: a few pulses at a time on the calling thread, for live emulation.
#include "mirage/render/window_renderer.hpp"

#include "ray_batch.hpp"
#include "shading.hpp"

namespace mirage::render {

// The setup is copied: PulseShader refers to its environment and options, and callers may pass
// temporaries. Its scene, renderer and sensor must outlive the WindowRenderer.
struct WindowRenderer::Impl {
    explicit Impl(const Setup& s) : setup(s), shader(setup) {}
    Setup setup;
    PulseShader shader;  // after setup, which it refers to
    RayBatch g;
    std::vector<Hit> hits;
    ShadeScratch scratch;
    ShadedPoints result;
};

WindowRenderer::WindowRenderer(const Setup& setup) : impl_(std::make_unique<Impl>(setup)) {}

WindowRenderer::~WindowRenderer() = default;

void WindowRenderer::render(const core::Trajectory& trajectory, std::uint64_t first, std::size_t n,
                            std::vector<core::PointRecord>& out, RenderStats& stats) {
    Impl& m = *impl_;
    const RayBatchBuilder builder(m.setup.sensor, trajectory, m.setup.mount, m.setup.options.start);
    m.result.points.swap(out);
    m.result.samples.clear();
    m.result.stats = {};
    builder.for_each_batch(first, n, m.g, [&](RayBatch& g) {
        m.shader.trace(g, m.hits);
        m.shader.shade(g, m.hits, builder.subrays(), m.scratch, m.result);
    });
    m.result.points.swap(out);
    stats.add(m.result.stats);
}

}  // namespace mirage::render
