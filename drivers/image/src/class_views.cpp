// SPDX-License-Identifier: Apache-2.0
#include "mirage/image/class_views.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "mirage/core/error.hpp"

namespace mirage::image {
namespace {

// The frame's axes: u along the heading, v to its left; both from the centre.
struct Axes {
    Eigen::Vector2d c, u, v;
    explicit Axes(const GroundFrame& f)
        : c(f.centre), u(std::cos(f.heading), std::sin(f.heading)), v(-u.y(), u.x()) {}
};

int pixels(double extent, double pixel, const char* what) {
    const double n = std::ceil(extent / pixel);
    if (!(pixel > 0.0) || !(n >= 1.0) || n > 4096.0)
        throw ConfigError(std::string("class view: the frame's ") + what +
                          " must span 1 to 4096 pixels");
    return static_cast<int>(n);
}

void paint(RgbImage& img, int row, int col, std::uint8_t cls) {
    const auto c = class_colour(cls);
    std::uint8_t* p = img.at(row, col);
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
}

// Each pixel as zoom × zoom.
RgbImage zoomed(const RgbImage& img, int zoom) {
    if (zoom < 1 || zoom > 16) throw ConfigError("class view: zoom must be 1 to 16");
    RgbImage out(img.width * zoom, img.height * zoom);
    for (int r = 0; r < out.height; ++r)
        for (int c = 0; c < out.width; ++c)
            std::copy_n(img.at(r / zoom, c / zoom), 3, out.at(r, c));
    return out;
}

}  // namespace

std::array<std::uint8_t, 3> class_colour(std::uint8_t classification) {
    switch (classification) {
        case 2:
            return {170, 150, 110};
        case 5:
            return {60, 150, 60};
        case 6:
            return {150, 150, 160};
        case 11:
            return {80, 80, 85};
        case 18:
            return {110, 40, 40};
        case 64:
            return {220, 50, 40};
        case 65:
            return {255, 150, 20};
        case 66:
            return {120, 240, 90};
        default:
            return {255, 255, 255};
    }
}

RgbImage render_lowest_by_class(std::span<const core::PointRecord> pts, const GroundFrame& f) {
    const int w = pixels(f.length, f.pixel_m, "length"), h = pixels(f.width, f.pixel_m, "width");
    const Axes a(f);
    std::vector<double> low(std::size_t(w) * std::size_t(h),
                            std::numeric_limits<double>::infinity());
    RgbImage img(w, h);
    for (const auto& p : pts) {
        const Eigen::Vector2d d = Eigen::Vector2d(p.x, p.y) - a.c;
        const double cu = (d.dot(a.u) + f.length / 2) / f.pixel_m;
        const double rv = (f.width / 2 - d.dot(a.v)) / f.pixel_m;  // row 0 on the left side
        if (!(cu >= 0 && cu < w && rv >= 0 && rv < h) || !std::isfinite(p.z) ||
            p.classification == 18)
            continue;
        const int col = static_cast<int>(cu), row = static_cast<int>(rv);
        double& z = low[std::size_t(row) * std::size_t(w) + std::size_t(col)];
        if (p.z >= z) continue;
        z = p.z;
        paint(img, row, col, p.classification);
    }
    return zoomed(img, f.zoom);
}

RgbImage render_section_by_class(std::span<const core::PointRecord> pts, const GroundFrame& f,
                                 double z0, double z1) {
    const int w = pixels(f.length, f.pixel_m, "length");
    const int h = pixels(z1 - z0, f.pixel_m, "height");
    const Axes a(f);
    std::vector<std::map<std::uint8_t, std::uint32_t>> count(std::size_t(w) * std::size_t(h));
    for (const auto& p : pts) {
        const Eigen::Vector2d d = Eigen::Vector2d(p.x, p.y) - a.c;
        const double cu = (d.dot(a.u) + f.length / 2) / f.pixel_m;
        const double rz = (z1 - p.z) / f.pixel_m;
        if (!(cu >= 0 && cu < w && rz >= 0 && rz < h) || std::abs(d.dot(a.v)) > f.width / 2)
            continue;
        count[std::size_t(rz) * std::size_t(w) + std::size_t(cu)][p.classification]++;
    }
    RgbImage img(w, h);
    for (int row = 0; row < h; ++row)
        for (int col = 0; col < w; ++col) {
            const auto& m = count[std::size_t(row) * std::size_t(w) + std::size_t(col)];
            std::uint32_t best = 0;
            std::uint8_t cls = 0;
            for (const auto& [c, n] : m)
                if (n > best) best = n, cls = c;
            if (best) paint(img, row, col, cls);
        }
    return zoomed(img, f.zoom);
}

}  // namespace mirage::image
