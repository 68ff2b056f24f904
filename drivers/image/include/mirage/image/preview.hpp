// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "mirage/core/point.hpp"
#include "mirage/image/png_writer.hpp"

namespace mirage::image {

enum class TopdownMode { Height, Intensity };
enum class RangeImageLayout { Spinning, Airborne };

// Perceptual (viridis-like, dark blue-violet -> yellow) colour map: nine stops, linearly
// interpolated; t is clamped to [0, 1]. Never pure black, so empty pixels stay distinguishable.
std::array<std::uint8_t, 3> colormap(double t);

// Top-down raster over the x/y bounds of the points (local frame, north up: row 0 = max y).
// Each pixel keeps its highest point. The pixel grows beyond pixel_m when needed so neither
// side exceeds max_side. Height: colormap over the 1st..99th percentile of the kept heights.
// Intensity: grey = 32 + 223·clamp((I − I1)/(I99 − I1)) (percentiles of the kept intensities;
// LAS intensity is already log-calibrated), so a hit is never black. Empty pixels (and no points at
// all: a 1x1 image) are black. Non-finite points are skipped. Throws ConfigError on pixel_m <= 0 or
// max_side < 1.
RgbImage render_topdown(std::span<const core::PointRecord> pts, TopdownMode mode,
                        double pixel_m = 0.5, int max_side = 2048);

// Range image, rows x cols, coloured by range_m (colormap over the drawn min..max); cells
// without a return are black; when several points fall in one cell the last one wins.
// Spinning: row = point.channel (points with channel >= rows are dropped), column =
//   floor(azimuth_deg · cols / 360), wrapped into [0, cols). With several revolutions the
//   latest one shows.
// Airborne: cols must be the pulses per scan line. Lines are aligned on the first point
//   flagged edge_of_flight_line (its pulse ends a line; without any flag, on the lowest
//   pulse index), row = scan line counted from the first one, column = pulse offset in its
//   line (firing order; a bidirectional mirror mirrors every other line). Pulses that missed
//   leave gaps rather than shifting the line. Lines beyond `rows` are dropped.
// Throws ConfigError when rows or cols is outside [1, 65536].
// row_scale > 1 repeats every row that many times (readable 16-beam images).
RgbImage render_range(std::span<const core::PointRecord> pts, int rows, int cols,
                      RangeImageLayout layout, int row_scale = 1);

// render_* then write_png; IoError names the file.
void write_topdown_png(const std::string& path, std::span<const core::PointRecord> pts,
                       TopdownMode mode, double pixel_m = 0.5, int max_side = 2048);
void write_range_png(const std::string& path, std::span<const core::PointRecord> pts, int rows,
                     int cols, RangeImageLayout layout, int row_scale = 1);

}  // namespace mirage::image
