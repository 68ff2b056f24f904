// SPDX-License-Identifier: Apache-2.0
#include "waveform_preview.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "mirage/core/error.hpp"
#include "mirage/image/waveform_plot.hpp"

namespace mirage::hil {
namespace {

// Points to plot: those asked for, or four pulses whose returns all lie in their packet: the most
// returns first, and of those the ones whose weakest return is strongest (a noise crossing
// makes a return too, but a faint one).
std::vector<std::uint64_t> chosen_points(const las::LasFile& f,
                                         const std::vector<std::uint64_t>& asked) {
    if (!asked.empty()) return asked;
    const auto& pts = f.points();
    struct Candidate {
        std::uint8_t returns;
        float weakest;
        std::uint64_t first;
    };
    std::vector<Candidate> c;
    for (std::uint64_t k = 0; k < pts.size(); ++k) {
        const std::uint64_t n = pts[k].number_of_returns;
        if (pts[k].return_number != 1 || n == 0 || k + n > pts.size()) continue;
        float weakest = INFINITY;
        bool whole = true;
        for (std::uint64_t j = k; j < k + n; ++j) {
            whole &= pts[j].wave_index != 0 && pts[j].wave_offset == pts[k].wave_offset;
            weakest = std::min(weakest, pts[j].amplitude);
        }
        if (whole) c.push_back({pts[k].number_of_returns, weakest, k});
    }
    const auto better = [](const Candidate& a, const Candidate& b) {
        return a.returns != b.returns ? a.returns > b.returns : a.weakest > b.weakest;
    };
    const std::size_t n = std::min<std::size_t>(4, c.size());
    std::partial_sort(c.begin(), c.begin() + static_cast<std::ptrdiff_t>(n), c.end(), better);
    std::vector<std::uint64_t> out;
    for (std::size_t k = 0; k < n; ++k) out.push_back(c[k].first);
    return out;
}

}  // namespace

void write_waveform_preview(const std::string& png, const las::LasFile& f,
                            const std::vector<std::uint64_t>& asked) {
    const auto& pts = f.points();
    std::vector<image::WaveformPanel> panels;
    for (const std::uint64_t k : chosen_points(f, asked)) {
        if (k >= pts.size())
            throw ConfigError(
                fmt::format("las-info: --points {}: the file has {} points", k, pts.size()));
        const las::LasPoint& p = pts[k];
        image::WaveformPanel panel{f.waveform(p), {}};
        if (panel.samples.empty())
            throw ConfigError(
                fmt::format("waveform preview: point {} has no valid waveform packet", k));
        const double spacing = f.descriptor(p.wave_index)->spacing_ps;
        std::string at;
        const std::uint64_t lo = k >= 15 ? k - 15 : 0,
                            hi = std::min<std::uint64_t>(k + 16, pts.size());
        for (std::uint64_t j = lo; j < hi; ++j) {
            if (pts[j].wave_index != p.wave_index || pts[j].wave_offset != p.wave_offset) continue;
            panel.returns.push_back(pts[j].wave_location_ps / spacing);
            at += fmt::format(" {:.0f}", pts[j].wave_location_ps);
        }
        fmt::print("  panel {}: point {}, GPS {:.6f}, returns at{} ps\n", panels.size(), k,
                   p.gps_time, at);
        panels.push_back(std::move(panel));
    }
    if (panels.empty())
        throw ConfigError("waveform preview: no point with a waveform packet to plot");
    image::write_waveforms_png(png, panels);
    fmt::print("  wrote {} ({} waveforms)\n", png, panels.size());
}

}  // namespace mirage::hil
