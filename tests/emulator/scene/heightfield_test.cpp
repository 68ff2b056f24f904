// SPDX-License-Identifier: Apache-2.0
#include "mirage/scene/heightfield.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "mesh_checks.hpp"
#include "mirage/core/error.hpp"
#include "mirage/scene/mesh_io.hpp"
#include "test_paths.hpp"

namespace mirage::scene {
namespace {

using test::expect_error;

std::string fixture(const std::string& name) {
    return (test::source_dir() / "recordings" / "scenes" / name).string();
}

TEST(Heightfield, function_grid_vertices_equal_the_function_exactly) {
    HeightFunction f;
    f.kind = HeightFunction::Kind::SineHills;
    f.amplitude_m = 3.0;
    f.wavelength_m = 16.0;
    f.height_m = 1.5;
    const HeightGrid g = grid_from_function(f, 20.0, 10.0, 0.5);  // 41 × 21 samples
    ASSERT_EQ(g.cols, 41);
    ASSERT_EQ(g.rows, 21);
    const Mesh m = mesh_from_grid(g, 2);
    EXPECT_EQ(m.triangles.size(), 2u * 40u * 20u);
    ASSERT_EQ(m.vertices.size(), 41u * 21u);
    for (const auto& v : m.vertices) {
        // x, y are multiples of 0.5 (exact in float), so z must be the float of f(x, y).
        EXPECT_EQ(v.z(), static_cast<float>(f(v.x(), v.y())));
    }
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        EXPECT_GT(test::face_normal(m, t).z(), 0) << "triangle " << t;
    }
    Eigen::AlignedBox3d box;
    for (const auto& v : m.vertices) box.extend(v.cast<double>());
    EXPECT_EQ(box.min().head<2>(), Eigen::Vector2d(-10, -5));
    EXPECT_EQ(box.max().head<2>(), Eigen::Vector2d(10, 5));
}

TEST(Heightfield, ramp_and_flat_functions_follow_their_formulas) {
    HeightFunction ramp;
    ramp.kind = HeightFunction::Kind::Ramp;
    ramp.height_m = 2;
    ramp.slope_x = 0.5;
    ramp.slope_y = -0.25;
    EXPECT_DOUBLE_EQ(ramp(4, 8), 2 + 2 - 2);
    HeightFunction flat;
    flat.height_m = -3;
    EXPECT_DOUBLE_EQ(flat(100, -7), -3);
    EXPECT_THROW(grid_from_function(flat, 10.0, 10.0, 3.0), ConfigError);  // not a multiple
    EXPECT_THROW(grid_from_function(flat, 1e6, 1e6, 0.01), ConfigError);   // too many samples
}

TEST(Heightfield, esri_ascii_grid_is_placed_at_cell_centres_without_nodata_cells) {
    const std::string text = read_file_bytes(fixture("hill.asc"), "asc");
    const HeightGrid g = parse_esri_ascii(text, "hill.asc", 2.0, 1.0);
    ASSERT_EQ(g.cols, 4);
    ASSERT_EQ(g.rows, 3);
    EXPECT_DOUBLE_EQ(g.x0_m, 500031.0);   // xllcorner + cell / 2
    EXPECT_DOUBLE_EQ(g.y0_m, 5000025.0);  // yllcorner + (rows − 0.5)·cell: northern row
    EXPECT_DOUBLE_EQ(g.at(0, 0), 1.0 + 2.0 * 0.5);
    EXPECT_DOUBLE_EQ(g.at(3, 2), 1.0 + 2.0 * 0.75);
    EXPECT_TRUE(std::isnan(g.at(2, 1)));
    HeightGrid local = g;
    local.x0_m -= 500000;
    local.y0_m -= 5000000;
    const Mesh m = mesh_from_grid(local, 0);
    // 3 × 2 cells, the 4 cells touching the no-data sample are left out.
    EXPECT_EQ(m.triangles.size(), 2u * 2u);
    EXPECT_EQ(m.vertices.size(), 11u);
    EXPECT_EQ(m.vertices[0], Eigen::Vector3f(31, 25, 2));
}

TEST(Heightfield, sixteen_bit_pgm_maps_counts_to_heights_centred_on_the_origin) {
    const std::string bytes = read_file_bytes(fixture("ramp.pgm"), "pgm");
    const HeightGrid g = parse_pgm(bytes, "ramp.pgm", 2.0, 0.001, -1.0);
    ASSERT_EQ(g.cols, 3);
    ASSERT_EQ(g.rows, 2);
    EXPECT_DOUBLE_EQ(g.x0_m, -2.0);
    EXPECT_DOUBLE_EQ(g.y0_m, 1.0);
    EXPECT_NEAR(g.at(1, 0), -1.0 + 1.0, 1e-12);  // a fused multiply-add may leave 1e-17
    EXPECT_DOUBLE_EQ(g.at(2, 1), -1.0 + 65.535);
    EXPECT_EQ(mesh_from_grid(g, 0).triangles.size(), 4u);
}

TEST(Heightfield, eight_bit_pgm_uses_one_byte_per_sample) {
    std::string pgm = "P5 2 2 200\n";
    pgm += std::string("\x00\x64\xc8\x0a", 4);
    const HeightGrid g = parse_pgm(pgm, "t.pgm", 1.0);
    EXPECT_DOUBLE_EQ(g.at(0, 0), 0);
    EXPECT_DOUBLE_EQ(g.at(1, 0), 100);
    EXPECT_DOUBLE_EQ(g.at(0, 1), 200);
    EXPECT_DOUBLE_EQ(g.at(1, 1), 10);
}

TEST(Heightfield, malformed_rasters_name_the_file_and_line) {
    expect_error(
        [] {
            parse_esri_ascii(
                "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                "1 2\n3 x\n",
                "a.asc");
        },
        {"asc 'a.asc'", "line 7", "malformed number 'x'"});
    expect_error(
        [] {
            parse_esri_ascii(
                "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                "1 2\n3\n",
                "b.asc");
        },
        {"asc 'b.asc'", "file ends after 3 of 4 values"});
    expect_error(
        [] {
            parse_esri_ascii(
                "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                "1 2\nnan 4\n",
                "n.asc");
        },
        {"asc 'n.asc'", "line 7", "non-finite"});
    expect_error(
        [] {
            parse_esri_ascii(
                "ncols 99999\nnrows 99999\nxllcorner 0\nyllcorner 0\n"
                "cellsize 1\n1 2\n",
                "huge.asc");
        },
        {"asc 'huge.asc'", "99999 × 99999"});
    expect_error([] { parse_esri_ascii("ncols 2\nnrows 2\nxllcorner 0\ncolour 3\n", "k.asc"); },
                 {"asc 'k.asc'", "line 4", "unknown header key 'colour'"});
    expect_error([] { parse_pgm(std::string("P5 4 4 255\n\x01\x02", 13), "t.pgm", 1.0); },
                 {"pgm 't.pgm'", "truncated", "16 bytes"});
    expect_error([] { parse_pgm("P2 2 2 255\n1 2 3 4\n", "a.pgm", 1.0); }, {"pgm 'a.pgm'", "P2"});
}

}  // namespace
}  // namespace mirage::scene
