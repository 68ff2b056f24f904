// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

namespace mirage::render {

struct RenderStats {
    std::uint64_t pulses = 0;
    std::uint64_t points = 0;
    std::uint64_t misses = 0;     // no geometry within max range
    std::uint64_t voids = 0;      // hit but N_laser < γ·ΔN
    std::uint64_t too_close = 0;  // hit nearer than min range
    std::uint64_t rays = 0;       // sub-rays traced
    // Paths beyond the first hit (docs/time-resolved.md §5): continuation segments traced, and
    // paths that could have gone on but met the depth limit or lost the roulette.
    std::uint64_t path_segments = 0;
    std::uint64_t paths_cut = 0;
    double seconds = 0;
    // CPU time per stage summed over threads (each worker's CPU clock per chunk, split between the
    // stages by the steady clock): where the time goes, independent of other processes.
    double cpu_rays_s = 0;    // pulse specs, poses, ray generation
    double cpu_trace_s = 0;   // Renderer::intersect
    double cpu_shade_s = 0;   // physics, noise, point records
    double cpu_output_s = 0;  // the sink: encoding (on the workers when it can) and writing

    // Adds the counts and CPU times of `s` (not its seconds).
    void add(const RenderStats& s) {
        cpu_rays_s += s.cpu_rays_s;
        cpu_trace_s += s.cpu_trace_s;
        cpu_shade_s += s.cpu_shade_s;
        cpu_output_s += s.cpu_output_s;
        pulses += s.pulses;
        points += s.points;
        misses += s.misses;
        voids += s.voids;
        too_close += s.too_close;
        rays += s.rays;
        path_segments += s.path_segments;
        paths_cut += s.paths_cut;
    }
};

}  // namespace mirage::render
