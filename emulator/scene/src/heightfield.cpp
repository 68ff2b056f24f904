// SPDX-License-Identifier: Apache-2.0
// Height grids: ESRI ASCII and PGM rasters, analytic functions, and their triangulation.
#include "mirage/scene/heightfield.hpp"

#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "mirage/core/error.hpp"
#include "text_util.hpp"

namespace mirage::scene {

namespace {

using detail::quote;

// 50 M samples (100 M triangles, ~2 GB of mesh) is far beyond any sensible scene; the limit
// turns a typo in a size into an error instead of an allocation failure.
constexpr std::uint64_t kMaxSamples = 50'000'000;

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

}  // namespace

Mesh mesh_from_grid(const HeightGrid& grid, std::uint32_t material) {
    if (grid.cols < 2 || grid.rows < 2) {
        throw ConfigError("scene: heightfield needs at least 2 × 2 samples, got " +
                          std::to_string(grid.cols) + " × " + std::to_string(grid.rows));
    }
    const auto cols = static_cast<std::size_t>(grid.cols);
    const auto rows = static_cast<std::size_t>(grid.rows);
    if (grid.z_m.size() != cols * rows) throw ConfigError("scene: heightfield size mismatch");
    Mesh m;
    m.name = "heightfield";
    std::vector<int> index(cols * rows, -1);
    m.vertices.reserve(cols * rows);
    for (std::size_t r = 0; r < rows; ++r) {
        const double y = grid.y0_m - static_cast<double>(r) * grid.cell_m;
        for (std::size_t c = 0; c < cols; ++c) {
            const double z = grid.z_m[r * cols + c];
            if (std::isnan(z)) continue;
            const double x = grid.x0_m + static_cast<double>(c) * grid.cell_m;
            index[r * cols + c] = static_cast<int>(m.vertices.size());
            m.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y),
                                    static_cast<float>(z));
        }
    }
    m.triangles.reserve(2 * (cols - 1) * (rows - 1));
    for (std::size_t r = 0; r + 1 < rows; ++r) {
        for (std::size_t c = 0; c + 1 < cols; ++c) {
            const int nw = index[r * cols + c], ne = index[r * cols + c + 1];
            const int sw = index[(r + 1) * cols + c], se = index[(r + 1) * cols + c + 1];
            if (nw < 0 || ne < 0 || sw < 0 || se < 0) continue;
            // Both halves counter-clockwise seen from above (normal +z).
            m.triangles.emplace_back(nw, sw, se);
            m.triangles.emplace_back(nw, se, ne);
        }
    }
    m.materials.assign(m.triangles.size(), material);
    return m;
}

HeightGrid parse_esri_ascii(std::string_view text, const std::string& name, double z_scale,
                            double z_offset) {
    std::size_t pos = 0;
    std::size_t line = 1;
    auto fail = [&](const std::string& msg) -> void {
        throw ConfigError("asc '" + name + "': line " + std::to_string(line) + ": " + msg);
    };
    auto next = [&]() -> std::string_view {
        while (pos < text.size() && (detail::is_space(text[pos]) || text[pos] == '\n')) {
            if (text[pos] == '\n') ++line;
            ++pos;
        }
        const std::size_t b = pos;
        while (pos < text.size() && !detail::is_space(text[pos]) && text[pos] != '\n') ++pos;
        return text.substr(b, pos - b);
    };

    long long ncols = -1, nrows = -1;
    double xll = NAN, yll = NAN, cell = NAN, nodata = NAN;
    bool corner_x = true, corner_y = true, have_nodata = false;
    std::string_view tok = next();
    // Header: "key value" pairs until the first token that is a number.
    while (!tok.empty() && !detail::parse_double(tok)) {
        const std::string key = lower(tok);
        const std::size_t key_line = line;
        const std::string_view val = next();
        if (line != key_line || val.empty()) fail("header key " + quote(tok) + " has no value");
        auto num = detail::parse_double(val);
        if (!num || !std::isfinite(*num)) fail("bad value " + quote(val) + " for " + key);
        auto as_count = [&]() {
            if (*num != std::floor(*num) || *num < 2 || *num > 1e9) {
                fail(key + " must be an integer >= 2, got " + quote(val));
            }
            return static_cast<long long>(*num);
        };
        if (key == "ncols") {
            ncols = as_count();
        } else if (key == "nrows") {
            nrows = as_count();
        } else if (key == "xllcorner" || key == "xllcenter") {
            xll = *num;
            corner_x = key == "xllcorner";
        } else if (key == "yllcorner" || key == "yllcenter") {
            yll = *num;
            corner_y = key == "yllcorner";
        } else if (key == "cellsize") {
            if (*num <= 0) fail("cellsize must be positive");
            cell = *num;
        } else if (key == "nodata_value") {
            nodata = *num;
            have_nodata = true;
        } else {
            fail("unknown header key " + quote(tok));
        }
        tok = next();
    }
    if (ncols < 0 || nrows < 0 || std::isnan(xll) || std::isnan(yll) || std::isnan(cell)) {
        fail("header needs ncols, nrows, xllcorner|xllcenter, yllcorner|yllcenter, cellsize");
    }
    const auto total = static_cast<std::uint64_t>(ncols) * static_cast<std::uint64_t>(nrows);
    // Every value takes at least 2 bytes ("0 "); check before allocating.
    if (total > kMaxSamples || total > (text.size() - (pos - tok.size())) / 2 + 1) {
        fail("header declares " + std::to_string(ncols) + " × " + std::to_string(nrows) +
             " values, more than the file (or the " + std::to_string(kMaxSamples) +
             "-sample limit) holds");
    }
    HeightGrid g;
    g.cols = static_cast<int>(ncols);
    g.rows = static_cast<int>(nrows);
    g.cell_m = cell;
    g.x0_m = corner_x ? xll + cell / 2 : xll;
    g.y0_m = (corner_y ? yll + cell / 2 : yll) + static_cast<double>(nrows - 1) * cell;
    g.z_m.reserve(total);
    for (std::uint64_t i = 0; i < total; ++i) {
        if (tok.empty()) {
            fail("file ends after " + std::to_string(i) + " of " + std::to_string(total) +
                 " values");
        }
        auto v = detail::parse_double(tok);
        if (!v) fail("malformed number " + quote(tok));
        if (have_nodata && *v == nodata) {
            g.z_m.push_back(std::numeric_limits<double>::quiet_NaN());
        } else {
            if (!std::isfinite(*v)) fail("non-finite height " + quote(tok));
            g.z_m.push_back(z_offset + z_scale * *v);
        }
        tok = next();
    }
    if (!tok.empty()) fail("more than ncols × nrows = " + std::to_string(total) + " values");
    return g;
}

HeightGrid parse_pgm(std::string_view bytes, const std::string& name, double cell_m, double z_scale,
                     double z_offset) {
    auto fail = [&](const std::string& msg) -> void {
        throw ConfigError("pgm '" + name + "': " + msg);
    };
    if (bytes.substr(0, 2) != "P5") {
        fail(bytes.substr(0, 2) == "P2" ? "ASCII PGM (P2) is not supported, use binary P5"
                                        : "not a binary PGM (no 'P5' magic)");
    }
    std::size_t pos = 2;
    auto header_int = [&](const char* what) {
        // Whitespace and '#' comments may precede each header number.
        for (;;) {
            while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos])))
                ++pos;
            if (pos < bytes.size() && bytes[pos] == '#') {
                while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
                continue;
            }
            break;
        }
        const std::size_t b = pos;
        while (pos < bytes.size() && std::isdigit(static_cast<unsigned char>(bytes[pos]))) ++pos;
        auto v = detail::parse_int(bytes.substr(b, pos - b));
        if (!v || pos - b > 9) fail(std::string("bad ") + what + " in header");
        return *v;
    };
    const long long w = header_int("width");
    const long long h = header_int("height");
    const long long maxval = header_int("maxval");
    if (w < 2 || h < 2) fail("image must be at least 2 × 2 pixels");
    if (maxval < 1 || maxval > 65535) fail("maxval must be 1..65535");
    if (pos >= bytes.size() || !std::isspace(static_cast<unsigned char>(bytes[pos]))) {
        fail("header must end with one whitespace character");
    }
    ++pos;
    const std::size_t bpp = maxval < 256 ? 1 : 2;
    const auto total = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
    if (total > kMaxSamples) fail("image larger than " + std::to_string(kMaxSamples) + " pixels");
    if (bytes.size() - pos < total * bpp) {
        fail("truncated: " + std::to_string(w) + " × " + std::to_string(h) + " pixels need " +
             std::to_string(total * bpp) + " bytes, " + std::to_string(bytes.size() - pos) +
             " present");
    }
    HeightGrid g;
    g.cols = static_cast<int>(w);
    g.rows = static_cast<int>(h);
    g.cell_m = cell_m;
    g.x0_m = -static_cast<double>(w - 1) * cell_m / 2;
    g.y0_m = static_cast<double>(h - 1) * cell_m / 2;
    g.z_m.resize(total);
    for (std::uint64_t i = 0; i < total; ++i) {
        const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + pos + i * bpp);
        const unsigned v =
            bpp == 1 ? p[0] : (static_cast<unsigned>(p[0]) << 8) | p[1];  // big-endian
        g.z_m[i] = z_offset + z_scale * static_cast<double>(v);
    }
    return g;
}

double HeightFunction::operator()(double x, double y) const {
    switch (kind) {
        case Kind::Flat:
            return height_m;
        case Kind::Ramp:
            return height_m + slope_x * x + slope_y * y;
        case Kind::SineHills: {
            const double k = 2 * std::numbers::pi / wavelength_m;
            return height_m + amplitude_m * std::sin(k * x) * std::sin(k * y);
        }
    }
    return height_m;
}

HeightGrid grid_from_function(const HeightFunction& f, double width_m, double length_m,
                              double cell_m) {
    auto cells = [&](double size, const char* what) {
        if (!std::isfinite(size) || size <= 0 || !std::isfinite(cell_m) || cell_m <= 0) {
            throw ConfigError(std::string("scene: heightfield ") + what +
                              " and cell size must be positive");
        }
        const double n = std::round(size / cell_m);
        if (n < 1 || std::abs(n * cell_m - size) > 1e-6 * size) {
            throw ConfigError(std::string("scene: heightfield ") + what + " " +
                              std::to_string(size) + " is not a multiple of cell size " +
                              std::to_string(cell_m));
        }
        if (n + 1 > static_cast<double>(kMaxSamples)) {
            throw ConfigError("scene: heightfield too large");
        }
        return static_cast<long long>(n);
    };
    const long long nx = cells(width_m, "width");
    const long long ny = cells(length_m, "length");
    if (static_cast<double>(nx + 1) * static_cast<double>(ny + 1) >
        static_cast<double>(kMaxSamples)) {
        throw ConfigError("scene: heightfield of " + std::to_string(nx + 1) + " × " +
                          std::to_string(ny + 1) + " samples exceeds the " +
                          std::to_string(kMaxSamples) + "-sample limit");
    }
    HeightGrid g;
    g.cols = static_cast<int>(nx + 1);
    g.rows = static_cast<int>(ny + 1);
    g.cell_m = cell_m;
    g.x0_m = -width_m / 2;
    g.y0_m = length_m / 2;
    g.z_m.resize(static_cast<std::size_t>(g.cols) * static_cast<std::size_t>(g.rows));
    for (int r = 0; r < g.rows; ++r) {
        const double y = g.y0_m - r * cell_m;
        for (int c = 0; c < g.cols; ++c) {
            const double x = g.x0_m + c * cell_m;
            g.z_m[static_cast<std::size_t>(r) * static_cast<std::size_t>(g.cols) +
                  static_cast<std::size_t>(c)] = f(x, y);
        }
    }
    return g;
}

}  // namespace mirage::scene
