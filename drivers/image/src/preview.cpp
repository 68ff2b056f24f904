// SPDX-License-Identifier: Apache-2.0
#include "mirage/image/preview.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "mirage/core/error.hpp"

namespace mirage::image {
namespace {

// Nine samples along a viridis-like ramp (monotonic lightness, blue-violet to yellow).
constexpr std::array<std::array<std::uint8_t, 3>, 9> kStops = {{{68, 1, 84},
                                                                {71, 44, 122},
                                                                {59, 81, 139},
                                                                {44, 113, 142},
                                                                {33, 144, 141},
                                                                {39, 173, 129},
                                                                {92, 200, 99},
                                                                {170, 220, 50},
                                                                {253, 231, 37}}};

// Value at quantile q of v (v is reordered).
double quantile(std::vector<double>& v, double q) {
    const auto k = static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
}

void put(RgbImage& img, std::size_t cell, std::array<std::uint8_t, 3> c) {
    std::copy(c.begin(), c.end(), img.rgb.begin() + static_cast<std::ptrdiff_t>(cell * 3));
}

}  // namespace

std::array<std::uint8_t, 3> colormap(double t) {
    if (!(t > 0.0)) t = 0.0;  // also catches NaN
    if (t > 1.0) t = 1.0;
    const double s = t * static_cast<double>(kStops.size() - 1);
    const auto i = std::min(static_cast<std::size_t>(s), kStops.size() - 2);
    const double w = s - static_cast<double>(i);
    std::array<std::uint8_t, 3> out{};
    for (int c = 0; c < 3; ++c) {
        const double v = (1.0 - w) * kStops[i][c] + w * kStops[i + 1][c];
        out[c] = static_cast<std::uint8_t>(std::lround(v));
    }
    return out;
}

RgbImage render_topdown(std::span<const core::PointRecord> pts, TopdownMode mode, double pixel_m,
                        int max_side) {
    if (!(pixel_m > 0.0) || !std::isfinite(pixel_m) || max_side < 1) {
        throw ConfigError("top-down preview: pixel size must be > 0 and max side >= 1");
    }
    double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
    for (const auto& p : pts) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
        x0 = std::min(x0, p.x);
        x1 = std::max(x1, p.x);
        y0 = std::min(y0, p.y);
        y1 = std::max(y1, p.y);
    }
    if (!(x1 >= x0)) return RgbImage(1, 1);  // no finite point

    const double extent = std::max(x1 - x0, y1 - y0);
    const double pixel = std::max(pixel_m, extent / max_side);
    const int w = std::min(max_side, static_cast<int>((x1 - x0) / pixel) + 1);
    const int h = std::min(max_side, static_cast<int>((y1 - y0) / pixel) + 1);
    const std::size_t cells = static_cast<std::size_t>(w) * h;
    std::vector<double> top(cells, -std::numeric_limits<double>::infinity());
    std::vector<std::uint16_t> intensity(cells, 0);
    for (const auto& p : pts) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
        const int col = std::min(w - 1, static_cast<int>((p.x - x0) / pixel));
        const int row = h - 1 - std::min(h - 1, static_cast<int>((p.y - y0) / pixel));
        const std::size_t cell = static_cast<std::size_t>(row) * w + col;
        if (p.z > top[cell]) {
            top[cell] = p.z;
            intensity[cell] = p.intensity;
        }
    }

    std::vector<double> kept;
    for (std::size_t c = 0; c < cells; ++c) {
        if (std::isfinite(top[c])) {
            kept.push_back(mode == TopdownMode::Height ? top[c] : intensity[c]);
        }
    }
    RgbImage img(w, h);
    if (mode == TopdownMode::Height) {
        const double lo = quantile(kept, 0.01);
        const double hi = quantile(kept, 0.99);
        const double span = hi > lo ? hi - lo : 1.0;
        for (std::size_t c = 0; c < cells; ++c) {
            if (std::isfinite(top[c])) put(img, c, colormap((top[c] - lo) / span));
        }
    } else {
        // LAS intensity is already a log calibration of the signal, so a linear stretch between
        // the 1st and 99th percentiles shows it best (a second log would wash everything white).
        const double lo = quantile(kept, 0.01);
        const double hi = quantile(kept, 0.99);
        const double span = hi > lo ? hi - lo : 1.0;
        for (std::size_t c = 0; c < cells; ++c) {
            if (!std::isfinite(top[c])) continue;
            const double t = std::clamp((intensity[c] - lo) / span, 0.0, 1.0);
            const auto g = static_cast<std::uint8_t>(std::lround(32.0 + 223.0 * t));
            put(img, c, {g, g, g});
        }
    }
    return img;
}

RgbImage render_range(std::span<const core::PointRecord> pts, int rows, int cols,
                      RangeImageLayout layout, int row_scale) {
    if (row_scale > 1) {
        // Repeat each row so a 16-beam image is tall enough to read.
        const RgbImage one = render_range(pts, rows, cols, layout, 1);
        RgbImage tall(one.width, one.height * row_scale);
        for (int r = 0; r < tall.height; ++r)
            std::copy_n(one.at(r / row_scale, 0), static_cast<std::size_t>(one.width) * 3,
                        tall.at(r, 0));
        return tall;
    }
    constexpr int kMaxSide = 65536;
    if (rows < 1 || cols < 1 || rows > kMaxSide || cols > kMaxSide) {
        throw ConfigError("range preview: rows and cols must be in [1, 65536], got " +
                          std::to_string(rows) + "x" + std::to_string(cols));
    }
    const std::size_t cells = static_cast<std::size_t>(rows) * cols;
    std::vector<float> range(cells, 0.0f);  // 0 = no return

    if (layout == RangeImageLayout::Spinning) {
        for (const auto& p : pts) {
            if (p.channel >= rows || !std::isfinite(p.azimuth_deg)) continue;
            const double c = std::floor(static_cast<double>(p.azimuth_deg) * cols / 360.0);
            const auto col = static_cast<int>(std::fmod(std::fmod(c, cols) + cols, cols));
            range[static_cast<std::size_t>(p.channel) * cols + static_cast<std::size_t>(col)] =
                p.range_m;
        }
    } else if (!pts.empty()) {
        const std::int64_t n = cols;
        std::int64_t lowest = std::numeric_limits<std::int64_t>::max();
        std::int64_t phase = -1;
        for (const auto& p : pts) {
            const auto pulse = static_cast<std::int64_t>(p.pulse);
            lowest = std::min(lowest, pulse);
            if (phase < 0 && p.edge_of_flight_line) phase = (pulse + 1) % n;
        }
        if (phase < 0) phase = lowest % n;
        // Floor division: line k holds pulses phase + k·n .. phase + k·n + n − 1.
        const auto line_of = [&](std::int64_t pulse) {
            const std::int64_t d = pulse - phase;
            return d >= 0 ? d / n : -((-d + n - 1) / n);
        };
        const std::int64_t first = line_of(lowest);
        for (const auto& p : pts) {
            const auto pulse = static_cast<std::int64_t>(p.pulse);
            const std::int64_t line = line_of(pulse);
            const std::int64_t row = line - first;
            if (row >= rows) continue;
            const std::int64_t col = pulse - phase - line * n;
            range[static_cast<std::size_t>(row * n + col)] = p.range_m;
        }
    }

    float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
    for (float r : range) {
        if (r > 0.0f && std::isfinite(r)) {
            lo = std::min(lo, r);
            hi = std::max(hi, r);
        }
    }
    RgbImage img(cols, rows);
    const double span = hi > lo ? static_cast<double>(hi - lo) : 1.0;
    for (std::size_t c = 0; c < cells; ++c) {
        if (range[c] > 0.0f && std::isfinite(range[c])) {
            put(img, c, colormap((range[c] - lo) / span));
        }
    }
    return img;
}

void write_topdown_png(const std::string& path, std::span<const core::PointRecord> pts,
                       TopdownMode mode, double pixel_m, int max_side) {
    write_png(path, render_topdown(pts, mode, pixel_m, max_side));
}

void write_range_png(const std::string& path, std::span<const core::PointRecord> pts, int rows,
                     int cols, RangeImageLayout layout, int row_scale) {
    write_png(path, render_range(pts, rows, cols, layout, row_scale));
}

}  // namespace mirage::image
