// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace mirage::image {

// 8-bit RGB raster, row-major from the top-left pixel, 3 bytes per pixel.
struct RgbImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;  // width · height · 3

    RgbImage() = default;
    RgbImage(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0) {}
    std::uint8_t* at(int row, int col) {
        return rgb.data() + (static_cast<std::size_t>(row) * width + col) * 3;
    }
    const std::uint8_t* at(int row, int col) const {
        return rgb.data() + (static_cast<std::size_t>(row) * width + col) * 3;
    }
};

// Writes an 8-bit RGB PNG with libpng. Throws IoError naming the file when it cannot be
// created or written (a partly written file is removed), and ConfigError for an empty image
// or one whose buffer does not match its size.
void write_png(const std::string& path, const RgbImage& image);

}  // namespace mirage::image
