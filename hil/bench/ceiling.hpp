// SPDX-License-Identifier: Apache-2.0
// The bare Embree ceiling of the pipeline (`mirage bench`): the pipeline's own rays, batches and
// thread layout, with only the Renderer::intersect calls timed.
#pragma once
#include <cstdint>
#include <vector>

#include "mirage/render/setup.hpp"

namespace mirage::hil {

struct Ceiling {
    std::uint64_t pulses = 0, rays = 0;
    double seconds = 0;  // tracing alone, as the pipeline's threads would share it (makespan)
    double pulses_per_s() const { return seconds > 0 ? double(pulses) / seconds : 0.0; }
    double rays_per_s() const { return seconds > 0 ? double(rays) / seconds : 0.0; }
};

// Traces the rays render(setup) would trace, batch by batch (render::TraceBatches: the
// pipeline's ray generation), on as many threads taking chunks in order as render() uses, and
// times each intersect call. The ceiling's time is the makespan of the chunks' tracing times
// scheduled as render() schedules chunks, so the pipeline, which also builds rays, shades and
// writes, cannot beat it beyond noise.
Ceiling trace_ceiling(const render::Setup& setup);

// Wall time of jobs taking `seconds` each, in order, on `threads` workers that each take the next
// job when free (greedy list scheduling: render()'s chunk hand-out).
double makespan(const std::vector<double>& seconds, int threads);

}  // namespace mirage::hil
