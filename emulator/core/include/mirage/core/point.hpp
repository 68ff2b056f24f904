// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "mirage/core/time.hpp"

namespace mirage::core {

// One lidar return as produced by the pipeline and consumed by every output (LAS, packets).
// Position is in the scene's local frame (double); add Georef::anchor() for world coordinates.
struct PointRecord {
    double x = 0, y = 0, z = 0;   // local frame, m
    GpsTime t{};                  // firing time of the pulse
    std::uint64_t pulse = 0;      // global pulse index
    float range_m = 0;            // measured range (with noise)
    float scan_angle_deg = 0;     // LAS scan angle: off-nadir / elevation, degrees
    float azimuth_deg = 0;        // sensor-frame azimuth, clockwise from +x, [0, 360)
    double n_laser = 0;           // photo-electrons of the return (before calibration)
    std::uint16_t intensity = 0;  // calibrated, 0..65535
    std::uint16_t channel = 0;    // laser / beam index
    std::uint16_t point_source_id = 0;
    std::uint16_t red = 0, green = 0, blue = 0;
    std::uint8_t return_number = 1;  // 1-based
    std::uint8_t number_of_returns = 1;
    std::uint8_t classification = 1;  // LAS class (1 = unclassified)
    std::uint8_t scan_direction = 0;  // LAS scan direction flag
    std::uint8_t edge_of_flight_line = 0;
};

}  // namespace mirage::core
