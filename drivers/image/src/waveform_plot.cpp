// SPDX-License-Identifier: Apache-2.0
#include "mirage/image/waveform_plot.hpp"

#include <algorithm>
#include <cmath>

#include "mirage/core/error.hpp"

namespace mirage::image {
namespace {

constexpr int kMargin = 4;

void put(RgbImage& img, int row, int col, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    if (row < 0 || col < 0 || row >= img.height || col >= img.width) return;
    std::uint8_t* p = img.at(row, col);
    p[0] = r;
    p[1] = g;
    p[2] = b;
}

// The panel whose top row is `top`: frame, return markers, then the samples joined by
// vertical runs between neighbouring columns (so steep edges stay connected).
void draw_panel(RgbImage& img, const WaveformPanel& p, int top, int width, int height) {
    const int x0 = kMargin, x1 = width - kMargin - 1, y0 = top + kMargin,
              y1 = top + height - kMargin - 1;
    for (int c = x0; c <= x1; ++c) put(img, y0, c, 200, 200, 200), put(img, y1, c, 200, 200, 200);
    for (int r = y0; r <= y1; ++r) put(img, r, x0, 200, 200, 200), put(img, r, x1, 200, 200, 200);
    const auto [lo_it, hi_it] = std::minmax_element(p.samples.begin(), p.samples.end());
    const double lo = *lo_it, span = std::max(1.0, double(*hi_it) - lo);
    const double n = double(p.samples.size());
    const auto col = [&](double s) {
        return x0 + 1 + static_cast<int>(std::lround(s / std::max(1.0, n - 1) * (x1 - x0 - 2)));
    };
    const auto row = [&](double v) {
        return y1 - 1 - static_cast<int>(std::lround((v - lo) / span * (y1 - y0 - 2)));
    };
    for (const double s : p.returns) {
        if (!(s >= 0 && s <= n - 1)) continue;
        for (int r = y0 + 1; r < y1; ++r) put(img, r, col(s), 230, 40, 40);
    }
    // Per pixel column, the samples linearly interpolated, joined to the previous column.
    int prev = row(p.samples[0]);
    for (int c = col(0.0); c <= col(n - 1); ++c) {
        const double s = double(c - x0 - 1) / std::max(1, x1 - x0 - 2) * std::max(1.0, n - 1);
        const auto k = std::min(static_cast<std::size_t>(s), p.samples.size() - 1);
        const std::size_t k1 = std::min(k + 1, p.samples.size() - 1);
        const double v = p.samples[k] + (s - double(k)) * (double(p.samples[k1]) - p.samples[k]);
        const int r = row(v);
        for (int y = std::min(prev, r); y <= std::max(prev, r); ++y) put(img, y, c, 20, 20, 60);
        prev = r;
    }
}

}  // namespace

RgbImage render_waveforms(const std::vector<WaveformPanel>& panels, int width, int height) {
    if (panels.empty()) throw ConfigError("waveform plot: no waveforms to draw");
    if (width < 16 || width > 4096 || height < 16 || height > 4096)
        throw ConfigError("waveform plot: panel size outside 16–4096 pixels");
    for (const auto& p : panels)
        if (p.samples.empty()) throw ConfigError("waveform plot: a waveform without samples");
    RgbImage img(width, height * static_cast<int>(panels.size()));
    std::fill(img.rgb.begin(), img.rgb.end(), std::uint8_t{255});
    for (std::size_t k = 0; k < panels.size(); ++k)
        draw_panel(img, panels[k], static_cast<int>(k) * height, width, height);
    return img;
}

void write_waveforms_png(const std::string& path, const std::vector<WaveformPanel>& panels,
                         int width, int height) {
    write_png(path, render_waveforms(panels, width, height));
}

}  // namespace mirage::image
