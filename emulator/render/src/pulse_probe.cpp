// SPDX-License-Identifier: Apache-2.0
#include "mirage/render/pulse_probe.hpp"

#include <algorithm>

#include "ray_batch.hpp"
#include "shading.hpp"

namespace mirage::render {

std::vector<physics::Arrival> pulse_arrivals(const Setup& setup, std::uint64_t pulse) {
    const RayBatchBuilder builder(setup.sensor, setup.trajectory, setup.mount, setup.options.start);
    const PulseShader shader(setup);
    RayBatch g;
    builder.build(pulse, 1, g);
    std::vector<Hit> hits;
    shader.trace(g, hits);
    ShadeScratch scratch;
    RenderStats stats;
    scratch.paths = shader.trace_paths(g, hits, scratch, stats);
    shader.ray_terms(g, hits, scratch);
    std::vector<physics::Arrival> out;
    shader.pulse_arrivals(g, hits, scratch.ray_terms.data(), shader.weighted_k(builder.subrays()),
                          0, out, scratch.paths ? &scratch.path : nullptr);
    physics::sort_by_delay(out, scratch.sorted);
    return out;
}

}  // namespace mirage::render
