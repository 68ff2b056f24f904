// SPDX-License-Identifier: Apache-2.0
#include "summary.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace mirage::hil {

void print_summary(std::FILE* out, const char* what, const Job& job, const render::RenderStats& s) {
    const double secs = std::max(1e-9, s.seconds);
    const double sim = std::chrono::duration<double>(job.options.duration).count();
    fmt::print(out, "mirage {}: {} pulses, {} points, {} voids, {} misses, {} too close\n", what,
               s.pulses, s.points, s.voids, s.misses, s.too_close);
    if (s.path_segments > 0 || s.paths_cut > 0)
        fmt::print(out,
                   "  paths beyond the first hit: {} segments traced (in the physics share), {} "
                   "cut by the depth limit or the roulette\n",
                   s.path_segments, s.paths_cut);
    const auto& bs = job.renderer->build_stats();
    fmt::print(
        out,
        "  time {:.3f} s (scene {:.3f} s, BVH {:.3f} s): {:.3f} M pulses/s, {:.3f} M points/s, "
        "{:.1f}x real time ({} rays)\n",
        secs, job.scene_seconds, bs.build_seconds, double(s.pulses) / secs / 1e6,
        double(s.points) / secs / 1e6, sim / secs, s.rays);
    const double cpu = s.cpu_rays_s + s.cpu_trace_s + s.cpu_shade_s + s.cpu_output_s;
    if (cpu > 0) {
        fmt::print(
            out,
            "  CPU {:.3f} s: rays {:.0f} %, trace {:.0f} %, physics {:.0f} %, output {:.0f} %"
            " ({:.0f} ns per pulse outside the ray tracer)\n",
            cpu, 100 * s.cpu_rays_s / cpu, 100 * s.cpu_trace_s / cpu, 100 * s.cpu_shade_s / cpu,
            100 * s.cpu_output_s / cpu,
            1e9 * (cpu - s.cpu_trace_s) / double(std::max<std::uint64_t>(1, s.pulses)));
    }
}

void print_clock_steps(std::FILE* out, const hostclock::ClockStepFollower* clock) {
    if (clock == nullptr || clock->steps() == 0) return;
    std::fprintf(out, "  followed %llu step(s) of the host clock: timestamps %+.6f s\n",
                 static_cast<unsigned long long>(clock->steps()),
                 double(clock->step().load()) / 1e9);
}

}  // namespace mirage::hil
