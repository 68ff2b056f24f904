// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "mirage/scene/scene.hpp"

namespace mirage::scene {

// Regular grid of heights. Sample (col, row) sits at (x0 + col·cell, y0 − row·cell): row 0 is
// the northern edge, as in ESRI grids and images. NaN marks "no data".
struct HeightGrid {
    int cols = 0;
    int rows = 0;
    double x0_m = 0, y0_m = 0;  // position of sample (0, 0)
    double cell_m = 1.0;
    std::vector<double> z_m;  // rows·cols, row-major

    double at(int col, int row) const {
        return z_m[static_cast<std::size_t>(row) * static_cast<std::size_t>(cols) +
                   static_cast<std::size_t>(col)];
    }
};

// Triangulates a grid: one vertex per sample, 2 triangles per cell (split along the
// north-west/south-east diagonal, normals up). Cells touching a no-data sample are left out.
Mesh mesh_from_grid(const HeightGrid& grid, std::uint32_t material);

// ESRI ASCII grid (.asc): ncols, nrows, xllcorner|xllcenter, yllcorner|yllcenter, cellsize,
// optional nodata_value, then nrows·ncols heights. Samples are placed at their header
// coordinates (cell centres). Heights are z_offset + z_scale·value. ConfigError
// "asc '<name>': line N: ..." on bad content.
HeightGrid parse_esri_ascii(std::string_view text, const std::string& name, double z_scale = 1.0,
                            double z_offset = 0.0);
// Binary PGM (P5), 8-bit (maxval < 256) or 16-bit big-endian: sample values become
// z_offset + z_scale·value; the grid is centred on the origin with spacing cell_m.
// ConfigError "pgm '<name>': ..." on bad content.
HeightGrid parse_pgm(std::string_view bytes, const std::string& name, double cell_m,
                     double z_scale = 1.0, double z_offset = 0.0);

// Analytic terrains for heightfield objects (z in metres at local x, y):
//   flat:       z = height
//   ramp:       z = height + slope_x·x + slope_y·y
//   sine_hills: z = height + amplitude·sin(2πx/wavelength)·sin(2πy/wavelength)
struct HeightFunction {
    enum class Kind { Flat, Ramp, SineHills };
    Kind kind = Kind::Flat;
    double height_m = 0.0;
    double amplitude_m = 1.0;
    double wavelength_m = 100.0;
    double slope_x = 0.0, slope_y = 0.0;

    double operator()(double x, double y) const;
};

// Samples f on a width_m × length_m grid centred on the origin with spacing cell_m
// (width and length must be whole multiples of cell_m, within 1e-6 relative).
HeightGrid grid_from_function(const HeightFunction& f, double width_m, double length_m,
                              double cell_m);

}  // namespace mirage::scene
