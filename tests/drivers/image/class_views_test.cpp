// SPDX-License-Identifier: Apache-2.0
// Class-coloured views (docs/photon-counting.md §8): the lowest non-noise point per pixel from
// above, the most frequent class per pixel from the side, framed by a rotated ground rectangle.
#include "mirage/image/class_views.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "mirage/core/error.hpp"
#include "rgb_pixel.hpp"

namespace mirage::image {
namespace {

core::PointRecord classified_at(double x, double y, double z, std::uint8_t cls) {
    core::PointRecord p;
    p.x = x, p.y = y, p.z = z;
    p.classification = cls;
    return p;
}

using test::pixel;

TEST(ClassViews, top_down_keeps_the_lowest_point_that_is_not_noise) {
    // A 4 × 2 m frame of 1 m pixels centred on (10, 20), its long side along +y (heading 90°).
    const GroundFrame f{{10, 20}, std::numbers::pi / 2, 4, 2, 1.0, 3};
    const std::vector<core::PointRecord> pts = {
        classified_at(10.2, 21.5, 3.0, 66),   // net over ...
        classified_at(10.3, 21.6, 1.0, 65),   // ... the vehicle: lowest wins
        classified_at(10.3, 21.6, -5.0, 18),  // noise below the ground: skipped
        classified_at(9.5, 18.5, 0.0, 2),     // ground at the frame's start, on its left
        classified_at(30, 30, 0.0, 2),        // outside
    };
    const RgbImage img = render_lowest_by_class(pts, f);
    ASSERT_EQ(img.width, 12);  // 4 pixels × zoom 3
    ASSERT_EQ(img.height, 6);
    // (10.3, 21.6): 1.6 m along the heading (+y) from the centre -> column 3; 0.3 m to the
    // right of it (−x is left) -> row 1.
    EXPECT_EQ(pixel(img, 3 * 1, 3 * 3), class_colour(65));
    // (9.5, 18.5): 1.5 m before the centre -> column 0; 0.5 m to the left -> row 0.
    EXPECT_EQ(pixel(img, 0, 0), class_colour(2));
    int lit = 0;
    for (int r = 0; r < img.height; ++r)
        for (int c = 0; c < img.width; ++c)
            lit += pixel(img, r, c) != std::array<std::uint8_t, 3>{};
    EXPECT_EQ(lit, 2 * 9);
}

TEST(ClassViews, side_view_shows_the_most_frequent_class_in_the_slab) {
    const GroundFrame f{{0, 0}, 0.0, 2, 1, 0.5};
    std::vector<core::PointRecord> pts = {
        classified_at(0.1, 0.1, 0.1, 66), classified_at(0.2, -0.2, 0.2, 2),
        classified_at(0.3, 0.4, 0.3, 2), classified_at(0.1, 0.6, 0.1, 65)};
    const RgbImage img = render_section_by_class(pts, f, -1.0, 1.0);
    ASSERT_EQ(img.width, 4);
    ASSERT_EQ(img.height, 4);
    // x 0..0.5 -> column 2; z 0..0.5 -> row 1 (z1 = 1 at the top). Two ground, one net: ground;
    // the vehicle point lies 0.6 m across, outside the 1 m slab.
    EXPECT_EQ(pixel(img, 1, 2), class_colour(2));
    EXPECT_THROW(render_section_by_class(pts, f, 1.0, -1.0), ConfigError);
    EXPECT_THROW(render_lowest_by_class(pts, {{0, 0}, 0.0, 2, 1, 0.5, 17}), ConfigError);
}

}  // namespace
}  // namespace mirage::image
