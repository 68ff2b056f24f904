// SPDX-License-Identifier: Apache-2.0
#include "mirage/image/preview.hpp"

#include <gtest/gtest.h>
#include <png.h>

#include <filesystem>

#include "las_test_points.hpp"
#include "mirage/core/error.hpp"
#include "mirage/image/png_writer.hpp"
#include "rgb_pixel.hpp"
#include "test_paths.hpp"

namespace mirage::image {
namespace {

using test::pixel;
using test::TempDir;
using Rgb = std::array<std::uint8_t, 3>;

int lit_pixels(const RgbImage& img) {
    int n = 0;
    for (int r = 0; r < img.height; ++r) {
        for (int c = 0; c < img.width; ++c) n += pixel(img, r, c) != Rgb{0, 0, 0};
    }
    return n;
}

core::PointRecord at(double x, double y, double z, std::uint16_t intensity = 0) {
    core::PointRecord p;
    p.x = x;
    p.y = y;
    p.z = z;
    p.intensity = intensity;
    return p;
}

std::uint32_t be32(const std::vector<std::uint8_t>& b, std::size_t at) {
    return std::uint32_t{b[at]} << 24 | std::uint32_t{b[at + 1]} << 16 |
           std::uint32_t{b[at + 2]} << 8 | b[at + 3];
}

TEST(Colormap, runs_from_dark_violet_to_yellow_with_rising_lightness) {
    EXPECT_EQ(colormap(0.0), (Rgb{68, 1, 84}));
    EXPECT_EQ(colormap(1.0), (Rgb{253, 231, 37}));
    EXPECT_EQ(colormap(-3.0), colormap(0.0));
    EXPECT_EQ(colormap(7.0), colormap(1.0));
    EXPECT_EQ(colormap(std::nan("")), colormap(0.0));
    double last = -1;
    for (int i = 0; i <= 64; ++i) {
        const Rgb c = colormap(i / 64.0);
        const double luma = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        EXPECT_GT(luma, last) << i;
        last = luma;
    }
}

TEST(TopdownPreview, keeps_the_highest_point_per_pixel_north_up) {
    // Extent 10 m x 5 m at 0.5 m: 21 x 11 pixels.
    const std::vector<core::PointRecord> pts = {at(0, 0, 1.0, 100), at(0.1, 0.1, 5.0, 60000),
                                                at(10, 5, 3.0, 10)};
    const RgbImage h = render_topdown(pts, TopdownMode::Height, 0.5);
    ASSERT_EQ(h.width, 21);
    ASSERT_EQ(h.height, 11);
    EXPECT_EQ(lit_pixels(h), 2);
    EXPECT_EQ(pixel(h, 10, 0), colormap(1.0));  // south-west: z = 5 wins over z = 1
    EXPECT_EQ(pixel(h, 0, 20), colormap(0.0));  // north-east: z = 3, the lowest kept
    EXPECT_EQ(pixel(h, 5, 10), (Rgb{0, 0, 0}));

    const RgbImage g = render_topdown(pts, TopdownMode::Intensity, 0.5);
    EXPECT_EQ(pixel(g, 10, 0), (Rgb{255, 255, 255}));  // intensity of the highest point
    const auto grey = pixel(g, 0, 20)[0];
    EXPECT_EQ(grey, 32);  // the lowest kept intensity maps to the darkest grey of a hit
}

TEST(TopdownPreview, grows_the_pixel_to_respect_max_side_and_handles_no_points) {
    std::vector<core::PointRecord> pts = {at(0, 0, 0), at(1000, 250, 0)};
    const RgbImage img = render_topdown(pts, TopdownMode::Height, 0.5, 100);
    EXPECT_EQ(img.width, 100);
    EXPECT_EQ(img.height, 26);  // 250 m at 10 m per pixel + 1
    const RgbImage none = render_topdown({}, TopdownMode::Height);
    EXPECT_EQ(none.width, 1);
    EXPECT_EQ(none.height, 1);
    EXPECT_THROW(render_topdown(pts, TopdownMode::Height, 0.0), ConfigError);
}

TEST(RangePreview, spinning_rows_are_channels_and_columns_azimuth) {
    std::vector<core::PointRecord> pts;
    for (std::uint16_t ch = 0; ch < 4; ++ch) {
        core::PointRecord p;
        p.channel = ch;
        p.azimuth_deg = 90.0f * ch + 1.0f;
        p.range_m = 10.0f + 10.0f * ch;
        pts.push_back(p);
    }
    pts.push_back(pts[0]);
    pts.back().channel = 9;  // beyond the rows: dropped
    const RgbImage img = render_range(pts, 4, 8, RangeImageLayout::Spinning);
    EXPECT_EQ(lit_pixels(img), 4);
    EXPECT_EQ(pixel(img, 0, 0), colormap(0.0));
    EXPECT_EQ(pixel(img, 1, 2), colormap(1.0 / 3.0));
    EXPECT_EQ(pixel(img, 3, 6), colormap(1.0));
    EXPECT_EQ(pixel(img, 0, 1), (Rgb{0, 0, 0}));
}

TEST(RangePreview, airborne_rows_are_scan_lines_aligned_on_the_edge_flag) {
    // 10 pulses per line; pulse 9 ends a line; pulses 5..34 with every pulse ≡ 3 (mod 10) missed.
    std::vector<core::PointRecord> pts;
    for (std::uint64_t pulse = 5; pulse < 35; ++pulse) {
        if (pulse % 10 == 3) continue;
        core::PointRecord p;
        p.pulse = pulse;
        p.range_m = 100.0f + static_cast<float>(pulse);
        p.edge_of_flight_line = pulse % 10 == 9;
        pts.push_back(p);
    }
    const RgbImage img = render_range(pts, 3, 10, RangeImageLayout::Airborne);
    EXPECT_EQ(img.height, 3);
    EXPECT_EQ(img.width, 10);
    // Row 0: pulses 5..9 in columns 5..9; row 1: 10..19 except 13; row 2: 20..29 except 23;
    // pulses 30..34 are a fourth line and are dropped.
    EXPECT_EQ(lit_pixels(img), 5 + 9 + 9);
    EXPECT_EQ(pixel(img, 0, 4), (Rgb{0, 0, 0}));
    EXPECT_EQ(pixel(img, 0, 5), colormap(0.0));
    EXPECT_EQ(pixel(img, 1, 3), (Rgb{0, 0, 0}));
    EXPECT_NE(pixel(img, 1, 4), (Rgb{0, 0, 0}));
    EXPECT_EQ(pixel(img, 2, 9), colormap(1.0));
    EXPECT_THROW(render_range(pts, 0, 10, RangeImageLayout::Airborne), ConfigError);
}

TEST(PngWriter, file_has_png_signature_ihdr_and_the_same_pixels) {
    TempDir dir;
    const std::string path = dir.file("top.png");
    auto pts = test::make_points(2000, 8, 5, 31, 20.0);
    write_topdown_png(path, pts, TopdownMode::Height, 0.5);
    const RgbImage expected = render_topdown(pts, TopdownMode::Height, 0.5);
    const auto bytes = test::file_bytes(path);
    ASSERT_GE(bytes.size(), 33u);
    const std::uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    EXPECT_TRUE(std::equal(sig, sig + 8, bytes.begin()));
    EXPECT_EQ(be32(bytes, 8), 13u);  // IHDR length
    EXPECT_EQ(std::string(bytes.begin() + 12, bytes.begin() + 16), "IHDR");
    EXPECT_EQ(be32(bytes, 16), static_cast<std::uint32_t>(expected.width));
    EXPECT_EQ(be32(bytes, 20), static_cast<std::uint32_t>(expected.height));
    EXPECT_EQ(bytes[24], 8);        // bit depth
    EXPECT_EQ(bytes[25], 2);        // colour type RGB
    EXPECT_GT(expected.width, 70);  // ±20 m at 0.5 m

    // Decode with libpng's simplified API and compare every pixel.
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_file(&img, path.c_str()));
    img.format = PNG_FORMAT_RGB;
    std::vector<std::uint8_t> decoded(PNG_IMAGE_SIZE(img));
    ASSERT_TRUE(png_image_finish_read(&img, nullptr, decoded.data(), 0, nullptr));
    EXPECT_EQ(decoded, expected.rgb);
}

TEST(PngWriter, unwritable_path_throws_io_error_naming_it) {
    const std::string path = "/nonexistent-mirage-folder/p.png";
    try {
        write_png(path, RgbImage(2, 2));
        FAIL() << "no exception";
    } catch (const IoError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("png writer '" + path + "'", 0), 0u) << e.what();
    }
    EXPECT_THROW(write_png("/tmp/never.png", RgbImage()), ConfigError);
}

}  // namespace
}  // namespace mirage::image
