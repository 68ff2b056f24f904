// SPDX-License-Identifier: Apache-2.0
// Crosstalk in a Geiger-mode array (docs/photon-counting.md §2): an avalanche may fire each of
// its pixel's four neighbours at the same moment. For pixels that report their first detection
// only, a frame's outcome has a closed form that needs no time-ordered pass over its events.
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "mirage/physics/geiger.hpp"

namespace mirage::physics {

// The neighbours one detection fires, as bits.
enum CrosstalkFire : std::uint8_t { kFireLeft = 1, kFireRight = 2, kFireUp = 4, kFireDown = 8 };

// A detection's time and pixel, waiting to fire its neighbours.
struct CrosstalkFiring {
    double t_ns;
    std::uint32_t p;
};

// Which of each pixel's neighbours (left, right, up, down) its detection fires, into out[p]:
// direction s when the uniform of pixel p's word words[s][p] lies below `probability` and the
// neighbour is in the frame of `pixels` pixels, `columns` wide, row-major. One loop over the
// rows and columns whose compares, made on the words themselves, vectorise.
void crosstalk_fires(const std::array<const std::uint32_t*, 4>& words, double probability,
                     std::uint32_t columns, std::uint32_t pixels, std::uint8_t* out);

// One frame's crosstalk when every pixel reports its first detection only (max_events = 1), in
// place: events[p] holds pixel p's own first event (t_ns = +inf: none) and becomes the one it
// keeps. Pixel p fires at or after armed[p] (a dead time carried from an earlier frame; −inf:
// armed) and, when it detects, fires the neighbours fires[p] at the same time. Processing all
// events in time order, as a detector does, keeps for each pixel the earliest event reaching it
// at or after armed[p], its own on a tie; that is, the earliest own event over the chains of
// firings that reach it armed. `heap` is scratch. O(n + f log f) for f firing pixels.
void crosstalk_first_events(std::span<GeigerEvent> events, std::span<const double> armed,
                            std::span<const std::uint8_t> fires, std::uint32_t columns,
                            std::vector<CrosstalkFiring>& heap);

}  // namespace mirage::physics
