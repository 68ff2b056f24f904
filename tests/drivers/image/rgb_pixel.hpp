// SPDX-License-Identifier: Apache-2.0
// Pixel access shared by the image tests.
#pragma once
#include <array>
#include <cstdint>

#include "mirage/image/png_writer.hpp"

namespace mirage::test {

// The red, green and blue bytes of one pixel.
inline std::array<std::uint8_t, 3> pixel(const image::RgbImage& img, int row, int col) {
    const std::uint8_t* p = img.at(row, col);
    return {p[0], p[1], p[2]};
}

}  // namespace mirage::test
