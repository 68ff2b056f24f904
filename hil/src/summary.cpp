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
    const auto& bs = job.renderer->build_stats();
    fmt::print(
        out,
        "  time {:.3f} s (scene {:.3f} s, BVH {:.3f} s): {:.3f} M pulses/s, {:.3f} M points/s, "
        "{:.1f}x real time ({} rays)\n",
        secs, job.scene_seconds, bs.build_seconds, double(s.pulses) / secs / 1e6,
        double(s.points) / secs / 1e6, sim / secs, s.rays);
}

}  // namespace mirage::hil
