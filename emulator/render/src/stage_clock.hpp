// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <chrono>
#include <ctime>

#include "mirage/render/render_stats.hpp"

namespace mirage::render {

inline double thread_cpu_s() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// A worker's CPU time per stage over one chunk. The thread's CPU clock can be a system call (on
// virtual machines, thousands of cycles a read), so it is read once per chunk and split between
// the stages by the steady clock (a vDSO read).
class StageClock {
  public:
    enum Stage { kRays, kTrace, kShade, kOutput, kStages };
    StageClock() : cpu0_(thread_cpu_s()), last_(std::chrono::steady_clock::now()) {}
    void lap(Stage s) {
        const auto now = std::chrono::steady_clock::now();
        wall_[s] += now - last_;
        last_ = now;
    }
    void add_to(RenderStats& stats) const {
        std::chrono::steady_clock::duration wall{};
        for (const auto& w : wall_) wall += w;
        const double k =
            wall.count() > 0 ? (thread_cpu_s() - cpu0_) / static_cast<double>(wall.count()) : 0.0;
        stats.cpu_rays_s += k * static_cast<double>(wall_[kRays].count());
        stats.cpu_trace_s += k * static_cast<double>(wall_[kTrace].count());
        stats.cpu_shade_s += k * static_cast<double>(wall_[kShade].count());
        stats.cpu_output_s += k * static_cast<double>(wall_[kOutput].count());
    }

  private:
    double cpu0_;
    std::chrono::steady_clock::time_point last_;
    std::array<std::chrono::steady_clock::duration, kStages> wall_{};  // integer ticks
};

}  // namespace mirage::render
