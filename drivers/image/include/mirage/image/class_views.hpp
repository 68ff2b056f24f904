// SPDX-License-Identifier: Apache-2.0
// Views of a small area coloured by LAS class: what a simulation's truth says each point is
// (docs/photon-counting.md §8). Both views are framed by the caller, so views of several runs
// line up pixel for pixel.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>

#include "mirage/core/point.hpp"
#include "mirage/image/png_writer.hpp"

namespace mirage::image {

// The colour of a LAS class: 2 ground tan, 5 vegetation green, 6 building grey, 11 road dark
// grey, 18 noise dim red, 64 vehicle red, 65 vehicle under a net orange, 66 net bright green,
// any other white. Empty pixels stay black.
std::array<std::uint8_t, 3> class_colour(std::uint8_t classification);

// A frame on the ground: `centre` (local x, y), `heading` (rad from +x) of its long side,
// `length` along it and `width` across; pixels of `pixel_m`, each drawn `zoom` × `zoom`.
struct GroundFrame {
    Eigen::Vector2d centre{0, 0};
    double heading = 0, length = 20, width = 20, pixel_m = 0.25;
    int zoom = 1;
};

// Top-down over the frame (its long side to the right), each pixel the class of its lowest point
// not flagged noise (class 18): what lies under a net shows once any pulse found it. ConfigError
// for a frame of no pixels, more than 4096 a side, or a zoom outside 1..16.
RgbImage render_lowest_by_class(std::span<const core::PointRecord> pts, const GroundFrame& f);

// Side view of the frame's points (all across its width) from z0 up to z1: distance along the
// heading to the right, height up, each pixel the class of the most points in it.
RgbImage render_section_by_class(std::span<const core::PointRecord> pts, const GroundFrame& f,
                                 double z0, double z1);

}  // namespace mirage::image
