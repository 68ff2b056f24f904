// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "mirage/core/point.hpp"
#include "mirage/core/trajectory.hpp"
#include "mirage/render/render_stats.hpp"
#include "mirage/render/setup.hpp"

namespace mirage::render {

// Renders a few pulses at a time on the calling thread, for live emulation: a packet's worth of
// pulses just in time, with the poses an INS has reported by then. Same physics and per-pulse
// randomness as render(), so its points equal render()'s for the same pulses and poses. The
// setup is copied (its scene, renderer and sensor must outlive the WindowRenderer); its
// trajectory is not used: each window brings its own.
class WindowRenderer {
  public:
    explicit WindowRenderer(const Setup& setup);
    ~WindowRenderer();
    WindowRenderer(const WindowRenderer&) = delete;
    WindowRenderer& operator=(const WindowRenderer&) = delete;

    // Appends the points of pulses [first, first + n) (times from options.start) to `out`, with
    // poses from `trajectory`; adds to `stats`.
    void render(const core::Trajectory& trajectory, std::uint64_t first, std::size_t n,
                std::vector<core::PointRecord>& out, RenderStats& stats);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace mirage::render
