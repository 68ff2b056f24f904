// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <chrono>
#include <cstdint>

#include "mirage/render/pipeline.hpp"

namespace mirage::hil {

// Progress bar on stderr: percentage, pulses/s, points/s, ETA. Redraws at most 5 times a second
// on a terminal; elsewhere (CI logs) prints a plain line every 5 s.
class ProgressBar {
  public:
    explicit ProgressBar(std::uint64_t total_pulses);
    void update(const render::RenderStats& s);
    void finish(const render::RenderStats& s);

  private:
    void draw(const render::RenderStats& s, bool final);
    std::uint64_t total_;
    bool tty_;
    std::chrono::steady_clock::time_point last_{};
};

}  // namespace mirage::hil
