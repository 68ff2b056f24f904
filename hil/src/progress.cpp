// SPDX-License-Identifier: Apache-2.0
#include "progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace mirage::hil {

ProgressBar::ProgressBar(std::uint64_t total_pulses)
    : total_(std::max<std::uint64_t>(1, total_pulses)), tty_(::isatty(STDERR_FILENO) != 0) {}

void ProgressBar::update(const render::RenderStats& s) {
    const auto now = std::chrono::steady_clock::now();
    const auto gap = tty_ ? std::chrono::milliseconds(200) : std::chrono::milliseconds(5000);
    if (now - last_ < gap) return;
    last_ = now;
    draw(s, false);
}

void ProgressBar::finish(const render::RenderStats& s) { draw(s, true); }

void ProgressBar::draw(const render::RenderStats& s, bool final) {
    const double frac = std::min(1.0, double(s.pulses) / double(total_));
    const double secs = std::max(1e-9, s.seconds);
    const double pps = double(s.pulses) / secs, ptps = double(s.points) / secs;
    const double eta = pps > 0 ? double(total_ - std::min(total_, s.pulses)) / pps : 0.0;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    const std::string line =
        fmt::format("[{}] {:5.1f}%  {:.2f} Mpulses/s  {:.2f} Mpoints/s  ETA {:.1f} s", bar,
                    frac * 100.0, pps / 1e6, ptps / 1e6, eta);
    if (tty_)
        std::fprintf(stderr, "\r%s%s", line.c_str(), final ? "\n" : "");
    else
        std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
}

}  // namespace mirage::hil
